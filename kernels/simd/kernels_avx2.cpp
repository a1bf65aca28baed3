// Every kernel table of the library for AVX2 (simd/dispatch.hpp). This unit alone is compiled for
// AVX2 (kernels/CMakeLists.txt, beamtrace_isa_unit; -mfma too, but contraction is off, so no FMA is
// emitted) and instantiates every xsimd template for it. Kernels with no AVX2 form of their own
// come from the SSE4.2 table.
#include "bvh/wide_bvh_traversal_impl.hpp"
#include "simd/isa_unit.hpp"
#include "stream/group_traversal_impl.hpp"
#include "stream/ray_keys_impl.hpp"
#include "vlf/query/footprint_scan_impl.hpp"
#include "vlf/stream/tile_ray_batch_avx2_impl.hpp"

namespace beamtrace {
namespace {

using Unit = simd::UnitKernels<xsimd::avx2>;

std::uint32_t scan_footprints(const std::uint32_t* footprints, std::uint32_t count, std::uint32_t ray,
                              std::uint32_t* passing) {
    return vlf::scan_avx2(footprints, count, ray, passing);
}

}  // namespace

template <>
const TriangleKernels& simd::table<TriangleKernels, Isa::avx2>() {
    static const TriangleKernels k{Isa::avx2, table<TriangleKernels, Isa::sse42>().ray_x4, Unit::ray_one_register,
                                   Unit::packet_one_triangle, Unit::ray_corner_rows};
    return k;
}

template <>
const kdtree::PacketKernels& simd::table<kdtree::PacketKernels, Isa::avx2>() {
    static constexpr kdtree::PacketKernels k = Unit::packet_kernels(Isa::avx2);
    return k;
}

template <>
const vlf::VlfKernels& simd::table<vlf::VlfKernels, Isa::avx2>() {
    static constexpr vlf::VlfKernels k{
        Isa::avx2, Unit::lookup_packet,        scan_footprints,      vlf::occlude_entries_scalar,
        nullptr,   vlf::batch_candidates_avx2, vlf::batch_test_avx2, vlf::store_tile_rays_scalar};
    return k;
}

template <>
const stream::KeyKernels& simd::table<stream::KeyKernels, Isa::avx2>() {
    static constexpr stream::KeyKernels k{Isa::avx2, stream::KeyLanes<xsimd::avx2>::keys};
    return k;
}

template <>
const stream::GroupKernels& simd::table<stream::GroupKernels, Isa::avx2>() {
    static constexpr stream::GroupKernels k = stream::GroupLanes<xsimd::avx2>::table(Isa::avx2);
    return k;
}

template <>
const bvh::WideBvhKernels& simd::table<bvh::WideBvhKernels, Isa::avx2>() {
    static constexpr bvh::WideBvhKernels k = bvh::WideBvhTable<bvh::SimdLanes<xsimd::avx2>>::make(Isa::avx2);
    return k;
}

}  // namespace beamtrace
