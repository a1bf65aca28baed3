#pragma once
// Masked traversal of a group of up to 16 rays through the kd-tree, for rays of any directions
// (beyond the papers; docs/streams.md): every lane keeps its own interval, an inner node is one SIMD
// step for all lanes (each lane goes to the children its interval reaches, exactly as the single-ray
// traversal decides, with the same slack), and the group goes on depth first into the child the
// leading lane meets first. Lanes leave when occluded, or (closest hits) when the cells left lie
// beyond their closest hit. A leaf's triangles are tested 16 rays at a time when at least
// kPacketTestLanes lanes reach it, otherwise lane by lane as the single-ray traversal does.
//
// The group pays when its rays share the path to their cells: rays with one origin (the ambient-
// occlusion rays of one hit point) share every step from the root down to the origin's leaf and
// the tests of the cells around it. Answers: the single-ray traversal's (same triangle tests, same
// slack; of two hits at the same distance, either may be reported).
#include <cstdint>

#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "common/watertight_ray.hpp"
#include "kdtree/kd_node.hpp"
#include "simd/dispatch.hpp"

namespace beamtrace::stream {

inline constexpr int kPacketTestLanes = 4;

// The active lanes of `group`: closest hits into *hits (every lane written) or occlusion bits into
// *occluded. With kCount: counters->stream.group_steps, group_leaves and triangle_tests grow. By the
// kernels of the tree's instruction set (every one gives the same answers and counts).
template <bool kOcclusion, bool kCount>
void trace_group(const KdTree::Impl& kd, const Packet16& group, PacketHits16* hits, std::uint32_t* occluded,
                 QueryCounters* counters);

// A lane's set-up for the single-ray triangle kernels, for the kernels below. Compiled once, for the
// library's baseline: the per-ISA units that include group_traversal_impl.hpp must not compile
// copies of make_watertight_ray (an inline function) of their own (simd/isa_unit.hpp).
WatertightRay group_lane_ray(const Ray& r);

// The traversal at one instruction set's width (group_traversal_impl.hpp): trace[occlusion][count].
using TraceGroupFn = void (*)(const KdTree::Impl& kd, const Packet16& group, PacketHits16* hits,
                              std::uint32_t* occluded, QueryCounters* counters);
struct GroupKernels {
    Isa isa;
    TraceGroupFn trace[2][2];
};

}  // namespace beamtrace::stream

BEAMTRACE_KERNEL_TABLE(beamtrace::stream::GroupKernels);
