// Every kernel table of the library for AVX2 (simd/dispatch.hpp). This unit alone is compiled for
// AVX2 (kernels/CMakeLists.txt, beamtrace_isa_unit; -mfma too, but contraction is off, so no FMA is
// emitted) and instantiates every xsimd template for it. Kernels with no AVX2 form of their own
// come from the SSE4.2 table.
#include "common/triangle_kernels_impl.hpp"
#include "kdtree/packet/lane_box_test_impl.hpp"
#include "kdtree/packet/one_origin_frustum_impl.hpp"
#include "kdtree/packet/packet_kernels.hpp"
#include "simd/lane_bits.hpp"
#include "vlf/query/footprint_scan_impl.hpp"
#include "vlf/stream/packet_lookup_impl.hpp"
#include "vlf/vlf_kernels.hpp"

namespace beamtrace {
namespace {
namespace unit {  // this ISA's entry points (named apart from the templates they instantiate)

using Arch = xsimd::avx2;

void ray_x8(const WatertightRay& r, const Triangle* const* tris, int n, LaneHits& out) {
    out.mask = 0;
    simd::ray_xw<Arch>(r, tris, n, out, 0);
}
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
    return vlf::scan_avx2(footprints, count, ray, passing);
}

}  // namespace unit
}  // namespace

template <>
const TriangleKernels& simd::table<TriangleKernels, Isa::avx2>() {
    static const TriangleKernels k{Isa::avx2, table<TriangleKernels, Isa::sse42>().ray_x4, unit::ray_x8,
                                   unit::packet_x1};
    return k;
}

template <>
const kdtree::PacketKernels& simd::table<kdtree::PacketKernels, Isa::avx2>() {
    static constexpr kdtree::PacketKernels k{Isa::avx2, unit::frustum_cull, unit::lane_box};
    return k;
}

template <>
const vlf::VlfKernels& simd::table<vlf::VlfKernels, Isa::avx2>() {
    static constexpr vlf::VlfKernels k{
        Isa::avx2, unit::lookup_packet,          unit::scan_footprints, vlf::occlude_entries_scalar,
        nullptr,   vlf::batch_candidates_scalar, vlf::batch_test_scalar};
    return k;
}

}  // namespace beamtrace
