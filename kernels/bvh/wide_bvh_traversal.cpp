// The wide BVH's scalar reference table and the dispatch to the per-ISA tables.
#include "bvh/wide_bvh_traversal.hpp"

namespace beamtrace::bvh {
namespace {

template <bool kOcclusion>
Hit plain(const WideBvh& bvh, const Ray& ray) {
    return traverse_wide<ScalarLanes, kOcclusion, false>(bvh, ray, nullptr);
}
template <bool kOcclusion>
Hit counted(const WideBvh& bvh, const Ray& ray, QueryCounters* c) {
    return traverse_wide<ScalarLanes, kOcclusion, true>(bvh, ray, c);
}

}  // namespace

const WideBvhKernels& wide_bvh_kernels(Isa isa) { return simd::select<WideBvhKernels>(isa); }

}  // namespace beamtrace::bvh

template <>
const beamtrace::bvh::WideBvhKernels&
beamtrace::simd::table<beamtrace::bvh::WideBvhKernels, beamtrace::Isa::scalar>() {
    static constexpr beamtrace::bvh::WideBvhKernels k{
        beamtrace::Isa::scalar, beamtrace::bvh::plain<false>, beamtrace::bvh::plain<true>,
        beamtrace::bvh::counted<false>, beamtrace::bvh::counted<true>};
    return k;
}
