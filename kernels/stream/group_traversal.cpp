// Masked group traversal (group_traversal.hpp): the kernels of the tree's instruction set
// (group_traversal_impl.hpp, instantiated by the per-ISA units); the scalar table is SSE4.2's, the
// library's baseline.
#include "stream/group_traversal.hpp"

#include "common/triangle_kernels.hpp"

template <>
const beamtrace::stream::GroupKernels&
beamtrace::simd::table<beamtrace::stream::GroupKernels, beamtrace::Isa::scalar>() {
    return table<stream::GroupKernels, Isa::sse42>();
}

namespace beamtrace::stream {

WatertightRay group_lane_ray(const Ray& r) { return make_watertight_ray(r); }

template <bool kOcclusion, bool kCount>
void trace_group(const KdTree::Impl& kd, const Packet16& group, PacketHits16* hits, std::uint32_t* occluded,
                 QueryCounters* counters) {
    simd::select<GroupKernels>(kd.kernels->isa).trace[kOcclusion][kCount](kd, group, hits, occluded, counters);
}

template void trace_group<false, false>(const KdTree::Impl&, const Packet16&, PacketHits16*, std::uint32_t*,
                                        QueryCounters*);
template void trace_group<false, true>(const KdTree::Impl&, const Packet16&, PacketHits16*, std::uint32_t*,
                                       QueryCounters*);
template void trace_group<true, false>(const KdTree::Impl&, const Packet16&, PacketHits16*, std::uint32_t*,
                                       QueryCounters*);
template void trace_group<true, true>(const KdTree::Impl&, const Packet16&, PacketHits16*, std::uint32_t*,
                                      QueryCounters*);

}  // namespace beamtrace::stream
