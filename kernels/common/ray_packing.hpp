#pragma once
// Rays handed to packet queries 16 at a time (the span-of-rays calls of Mlrta and VisibilityField).
#include <algorithm>
#include <cstddef>
#include <span>

#include "beamtrace/ray.hpp"

namespace beamtrace {

// The packet of rays[first, first + 16): the last one of a span may be partial; its lanes past the
// end repeat the last ray (sane values) and are inactive. Returns the number of rays packed.
inline std::size_t pack_rays(std::span<const Ray> rays, std::size_t first, Packet16& packet) {
    const std::size_t n = std::min<std::size_t>(16, rays.size() - first);
    for (std::size_t i = 0; i < 16; ++i) packet.set_ray(int(i), rays[first + std::min(i, n - 1)]);
    packet.active = n == 16 ? 0xFFFFu : (1u << n) - 1u;
    return n;
}

}  // namespace beamtrace
