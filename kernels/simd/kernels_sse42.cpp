// Every kernel table of the library for SSE4.2 (simd/dispatch.hpp). This unit alone is compiled for
// SSE4.2 (kernels/CMakeLists.txt, beamtrace_isa_unit) and instantiates every xsimd template for it.
#include "bvh/wide_bvh_traversal_impl.hpp"
#include "simd/isa_unit.hpp"
#include "stream/group_traversal_impl.hpp"
#include "stream/ray_keys_impl.hpp"
#include "vlf/query/footprint_scan_impl.hpp"

namespace beamtrace {
namespace {

using Unit = simd::UnitKernels<xsimd::sse4_2>;

// One ray against 8 triangles as two halves of 4.
void ray_x8(const WatertightRay& r, const Triangle* const* tris, int n, LaneHits& out) {
    Unit::ray_one_register(r, tris, n < 4 ? n : 4, out);
    if (n > 4) simd::ray_xw<xsimd::sse4_2>(r, tris + 4, n - 4, out, 4);
}
std::uint32_t scan_footprints(const std::uint32_t* footprints, std::uint32_t count, std::uint32_t ray,
                              std::uint32_t* passing) {
    return vlf::scan_sse42(footprints, count, ray, passing);
}

}  // namespace

template <>
const TriangleKernels& simd::table<TriangleKernels, Isa::sse42>() {
    static constexpr TriangleKernels k{Isa::sse42, Unit::ray_one_register, ray_x8, Unit::packet_one_triangle,
                                       Unit::ray_corner_rows};
    return k;
}

template <>
const kdtree::PacketKernels& simd::table<kdtree::PacketKernels, Isa::sse42>() {
    static constexpr kdtree::PacketKernels k = Unit::packet_kernels(Isa::sse42);
    return k;
}

template <>
const vlf::VlfKernels& simd::table<vlf::VlfKernels, Isa::sse42>() {
    static constexpr vlf::VlfKernels k{
        Isa::sse42, Unit::lookup_packet,          scan_footprints,        vlf::occlude_entries_scalar,
        nullptr,    vlf::batch_candidates_scalar, vlf::batch_test_scalar, vlf::store_tile_rays_scalar};
    return k;
}

template <>
const stream::KeyKernels& simd::table<stream::KeyKernels, Isa::sse42>() {
    static constexpr stream::KeyKernels k{Isa::sse42, stream::KeyLanes<xsimd::sse4_2>::keys};
    return k;
}

template <>
const stream::GroupKernels& simd::table<stream::GroupKernels, Isa::sse42>() {
    static constexpr stream::GroupKernels k = stream::GroupLanes<xsimd::sse4_2>::table(Isa::sse42);
    return k;
}

template <>
const bvh::WideBvhKernels& simd::table<bvh::WideBvhKernels, Isa::sse42>() {
    static constexpr bvh::WideBvhKernels k = bvh::WideBvhTable<bvh::SimdLanes<xsimd::sse4_2>>::make(Isa::sse42);
    return k;
}

}  // namespace beamtrace
