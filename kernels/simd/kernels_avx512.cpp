// Every kernel table of the library for AVX-512 (simd/dispatch.hpp). This unit alone is compiled for
// AVX-512 (F, CD, DQ, BW, VL; kernels/CMakeLists.txt, beamtrace_isa_unit) and instantiates every
// xsimd template for it: the whole 4x4 packet in one register. Kernels with no AVX-512 form of their
// own come from the SSE4.2 and AVX2 tables.
// GCC 12 reports its own AVX-512 intrinsics (the _mm512_undefined_* pass-through operands of masked
// conversions, min and max) as reading uninitialised values; they are not.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include "common/triangle_kernels_impl.hpp"
#include "kdtree/packet/lane_box_test_impl.hpp"
#include "kdtree/packet/one_origin_frustum_impl.hpp"
#include "kdtree/packet/packet_kernels.hpp"
#include "simd/lane_bits.hpp"
#include "vlf/query/entry_closest_hit_impl.hpp"
#include "vlf/query/entry_occlusion_impl.hpp"
#include "vlf/query/footprint_scan_impl.hpp"
#include "vlf/stream/packet_lookup_impl.hpp"
#include "vlf/stream/tile_ray_batch_impl.hpp"
#include "vlf/vlf_kernels.hpp"

namespace beamtrace {
namespace {
namespace unit {  // this ISA's entry points (named apart from the templates they instantiate)

using Arch = xsimd::avx512bw;

void packet_x1(const WatertightPacket16& p, const Triangle& tri, LaneHits& out) { simd::packet_x1<Arch>(p, tri, out); }

std::uint32_t frustum_cull(const kdtree::OneOriginFrustum& f, const Triangle* tris, int n) {
    return kdtree::simd_impl::frustum_misses<Arch>(f, tris, n);
}
std::uint32_t lane_box(const kdtree::LaneBoxRays& s, const float* tfar, std::uint32_t lanes, const Box& box) {
    return kdtree::simd_impl::lanes_meeting<Arch>(s, tfar, lanes, box);
}

void lookup_packet(const vlf::LookupTables& t, const Packet16& p, vlf::PacketLookup& out, bool first_tiles) {
    vlf::lookup_packet_simd<Arch>(t, p, out, first_tiles);
}
std::uint32_t scan_footprints(const std::uint32_t* footprints, std::uint32_t count, std::uint32_t ray,
                              std::uint32_t* passing) {
    return vlf::scan_avx512(footprints, count, ray, passing);
}
vlf::EntriesAnswer occlude_entries(const WatertightRay& ray, const Triangle* triangles, const std::uint32_t* footprints,
                                   const std::uint32_t* ids, std::uint32_t count, std::uint32_t ray_footprint,
                                   bool distinct, std::uint32_t* hit) {
    return vlf::occlude_entries_avx512(ray, triangles, footprints, ids, count, ray_footprint, distinct, hit);
}
bool closest_entries(const WatertightRay& ray, const Triangle* triangles, const std::uint32_t* order,
                     const std::uint32_t* footprints, const std::uint32_t* ids, std::uint32_t count,
                     std::uint32_t ray_footprint, vlf::TestedIds& tested, Hit& best) {
    return vlf::closest_entries_avx512(ray, triangles, order, footprints, ids, count, ray_footprint, tested, best);
}
std::uint32_t batch_candidates(const std::uint32_t* groups, const std::uint32_t* footprints, const std::uint32_t* ids,
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
                                   table<TriangleKernels, Isa::avx2>().ray_x8, unit::packet_x1};
    return k;
}

template <>
const kdtree::PacketKernels& simd::table<kdtree::PacketKernels, Isa::avx512>() {
    static constexpr kdtree::PacketKernels k{Isa::avx512, unit::frustum_cull, unit::lane_box};
    return k;
}

template <>
const vlf::VlfKernels& simd::table<vlf::VlfKernels, Isa::avx512>() {
    static constexpr vlf::VlfKernels k{Isa::avx512,           unit::lookup_packet,   unit::scan_footprints,
                                       unit::occlude_entries, unit::closest_entries, unit::batch_candidates,
                                       unit::batch_test};
    return k;
}

}  // namespace beamtrace
#pragma GCC diagnostic pop
