#pragma once
// Ranges over the rays of several packets: what a beam (mlrta/beam.hpp) is made of. Over the lanes
// that are active and describe a segment (ray_validity.hpp) of every packet: the range of each
// direction component, of each start point coordinate (org + tnear dir), of the lengths, starts and
// ends measured along the first such lane's dominant axis, which signs the direction components
// take, whether one is zero, whether every origin is the first's. The reference here goes lane by
// lane; the kernel tables' forms (packet_setup_kernels.hpp) take 4, 8 or 16 lanes a step.
//
// Zeros are folded as +0 (x + 0.0f) and NaNs passed over (a lane whose main-axis component is 0 and
// whose tfar is infinite has a NaN length and end; its beam is incoherent, and they are never read):
// a minimum or maximum then does not depend on the order of the fold, so every form gives the
// reference's ranges bit for bit whatever its register width.
#include <cstdint>
#include <span>

#include "beamtrace/ray.hpp"
#include "common/interval.hpp"

namespace beamtrace::kdtree {

struct PacketSetRanges {
    std::uint32_t rays = 0;                 // lanes taken (none: every other field as initialised)
    int main_axis = 0;                      // dominant axis of the first lane taken (|x| >= |y| >= |z| on ties)
    Float3 first_origin;                    // of the first lane taken
    bool same_origin = true;                // every lane's origin == first_origin (float ==)
    bool zero = false;                      // some lane has a direction component equal to 0
    std::uint32_t signs[3] = {0, 0, 0};     // per axis: bit 0 some component negative (sign bit), bit 1 some not
    Interval dir[3], start[3];              // ranges of dir_k and of org_k + tnear dir_k
    Interval length, near, far;             // of (tfar - tnear) |dir_main|, tnear |dir_main|, tfar |dir_main|
};

using PacketSetRangesKernel = void (*)(std::span<const Packet16* const> packets, PacketSetRanges& out);

// The reference, lane by lane.
void packet_set_ranges(std::span<const Packet16* const> packets, PacketSetRanges& out);

// The dominant axis of a direction: x when |x| >= |y| and |x| >= |z|, else y when |y| >= |z|, else z.
inline int dominant_axis(float x, float y, float z) {
    const float ax = x < 0.0f ? -x : x, ay = y < 0.0f ? -y : y, az = z < 0.0f ? -z : z;
    return ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
}

}  // namespace beamtrace::kdtree
