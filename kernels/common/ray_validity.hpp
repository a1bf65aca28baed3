#pragma once
// Which rays describe a segment (the contract of beamtrace/ray.hpp): origin and direction finite, the
// direction not zero, tnear finite, tfar not NaN (+infinity is fine) and tnear <= tfar. Every query
// reports no hit (and no occlusion) for any other ray; engines test this once per ray or packet,
// before their set-up arithmetic, so a NaN or an infinity can never reach a cell or a beam.
#include <cstdint>

#include "beamtrace/ray.hpp"

namespace beamtrace {

// x - x is 0 for every finite x and NaN for infinities and NaNs: one sum tests ten values.
inline bool describes_segment(const Ray& r) {
    const float finite = ((r.org.x - r.org.x) + (r.org.y - r.org.y)) + ((r.org.z - r.org.z) + (r.dir.x - r.dir.x)) +
                         ((r.dir.y - r.dir.y) + (r.dir.z - r.dir.z)) + (r.tnear - r.tnear);
    const bool moves = r.dir.x != 0.0f || r.dir.y != 0.0f || r.dir.z != 0.0f;
    return finite == 0.0f && moves && r.tnear <= r.tfar;
}

// Bit i set when ray i of the packet describes a segment (active or not): describes_segment for the
// 16 lanes, four at a time (SSE, the library's baseline; out of line so that no wider instruction
// set's copy can be linked in).
std::uint32_t segment_lanes(const Packet16& p);

}  // namespace beamtrace
