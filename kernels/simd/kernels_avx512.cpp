// Every kernel table of the library for AVX-512 (simd/dispatch.hpp). This unit alone is compiled for
// AVX-512 (F, CD, DQ, BW, VL; kernels/CMakeLists.txt, beamtrace_isa_unit) and instantiates every
// xsimd template for it: the whole 4x4 packet in one register. Kernels with no AVX-512 form of their
// own come from the SSE4.2 and AVX2 tables.
// GCC 12 reports its own AVX-512 intrinsics (the _mm512_undefined_* pass-through operands of masked
// conversions, min and max) as reading uninitialised values; they are not.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include "bvh/wide_bvh_traversal_impl.hpp"
#include "simd/isa_unit.hpp"
#include "stream/group_traversal_impl.hpp"
#include "stream/ray_keys_impl.hpp"
#include "vlf/query/entry_closest_hit_impl.hpp"
#include "vlf/query/entry_occlusion_impl.hpp"
#include "vlf/query/footprint_scan_impl.hpp"
#include "vlf/stream/tile_ray_batch_impl.hpp"
#include "vlf/stream/tile_ray_store_impl.hpp"

namespace beamtrace {
namespace {
namespace unit {  // the entry points only AVX-512 has

using Unit = simd::UnitKernels<xsimd::avx512bw>;

std::uint32_t scan_footprints(const std::uint32_t* footprints, std::uint32_t count, std::uint32_t ray,
                              std::uint32_t* passing) {
    return vlf::scan_avx512(footprints, count, ray, passing);
}
vlf::EntriesAnswer occlude_entries(const WatertightRay& ray, const Triangle* triangles, const std::uint32_t* footprints,
                                   vlf::PackedIds ids, std::uint32_t count, std::uint32_t ray_footprint,
                                   bool distinct, std::uint32_t* hit) {
    return vlf::occlude_entries_avx512(ray, triangles, footprints, ids, count, ray_footprint, distinct, hit);
}
bool closest_entries(const WatertightRay& ray, const Triangle* triangles, const std::uint32_t* order,
                     const std::uint32_t* footprints, vlf::PackedIds ids, std::uint32_t count,
                     std::uint32_t ray_footprint, vlf::TestedIds& tested, Hit& best) {
    return vlf::closest_entries_avx512(ray, triangles, order, footprints, ids, count, ray_footprint, tested, best);
}
std::uint32_t batch_candidates(const std::uint32_t* groups, const std::uint32_t* footprints, vlf::PackedIds ids,
                               std::uint32_t first, std::uint32_t count, std::uint32_t ray_footprint, bool distinct,
                               std::uint32_t lane, std::uint32_t* out_ids, std::uint32_t* out_lanes) {
    return vlf::batch_candidates_avx512(groups, footprints, ids, first, count, ray_footprint, distinct, lane, out_ids,
                                        out_lanes);
}
std::uint32_t batch_test(const vlf::TileRayBatch& rays, const Triangle* triangles, const std::uint32_t* ids,
                         const std::uint32_t* lanes, std::uint32_t count, std::uint32_t occluded) {
    return vlf::batch_test_avx512(rays, triangles, ids, lanes, count, occluded);
}

}  // namespace unit
}  // namespace

template <>
const TriangleKernels& simd::table<TriangleKernels, Isa::avx512>() {
    static const TriangleKernels k{Isa::avx512, table<TriangleKernels, Isa::sse42>().ray_x4,
                                   table<TriangleKernels, Isa::avx2>().ray_x8, unit::Unit::packet_one_triangle,
                                   unit::Unit::ray_corner_rows};
    return k;
}

template <>
const kdtree::PacketKernels& simd::table<kdtree::PacketKernels, Isa::avx512>() {
    static constexpr kdtree::PacketKernels k = unit::Unit::packet_kernels(Isa::avx512);
    return k;
}

template <>
const vlf::VlfKernels& simd::table<vlf::VlfKernels, Isa::avx512>() {
    static constexpr vlf::VlfKernels k{Isa::avx512,           unit::Unit::lookup_packet,  unit::scan_footprints,
                                       unit::occlude_entries, unit::closest_entries,      unit::batch_candidates,
                                       unit::batch_test,      vlf::store_tile_rays_avx512};
    return k;
}

template <>
const stream::KeyKernels& simd::table<stream::KeyKernels, Isa::avx512>() {
    static constexpr stream::KeyKernels k{Isa::avx512, stream::KeyLanes<xsimd::avx512bw>::keys};
    return k;
}

template <>
const stream::GroupKernels& simd::table<stream::GroupKernels, Isa::avx512>() {
    static constexpr stream::GroupKernels k = stream::GroupLanes<xsimd::avx512bw>::table(Isa::avx512);
    return k;
}

template <>
const bvh::WideBvhKernels& simd::table<bvh::WideBvhKernels, Isa::avx512>() {
    static constexpr bvh::WideBvhKernels k = bvh::WideBvhTable<bvh::SimdLanes<xsimd::avx512bw>>::make(Isa::avx512);
    return k;
}

}  // namespace beamtrace
#pragma GCC diagnostic pop
