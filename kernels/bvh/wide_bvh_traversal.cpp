// The wide BVH's scalar reference table and the dispatch to the per-ISA tables.
#include "bvh/wide_bvh_traversal.hpp"

namespace beamtrace::bvh {

const WideBvhKernels& wide_bvh_kernels(Isa isa) { return simd::select<WideBvhKernels>(isa); }

}  // namespace beamtrace::bvh

template <>
const beamtrace::bvh::WideBvhKernels& beamtrace::simd::table<beamtrace::bvh::WideBvhKernels, beamtrace::Isa::scalar>() {
    static constexpr beamtrace::bvh::WideBvhKernels k =
        beamtrace::bvh::WideBvhTable<beamtrace::bvh::ScalarLanes>::make(beamtrace::Isa::scalar);
    return k;
}
