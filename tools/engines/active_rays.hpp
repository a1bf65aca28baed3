#pragma once
// The active rays of a ray set side by side (for the span-of-rays queries) and the slot of each.
#include <cstdint>
#include <vector>

#include "rays/ray_set.hpp"

namespace beamtrace::workload {

struct ActiveRays {
    std::vector<Ray> rays;
    std::vector<std::uint32_t> slots;
};

inline ActiveRays active_rays(const RaySet& set) {
    ActiveRays a;
    a.rays.reserve(set.ray_count);
    a.slots.reserve(set.ray_count);
    for (std::size_t p = 0; p < set.packets.size(); ++p)
        for (std::uint32_t m = set.packets[p].active & 0xFFFFu; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            a.rays.push_back(set.packets[p].ray(i));
            a.slots.push_back(std::uint32_t(p * 16 + std::size_t(i)));
        }
    return a;
}

}  // namespace beamtrace::workload
