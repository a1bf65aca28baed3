#pragma once
// The entry points every per-ISA unit (simd/kernels_<isa>.cpp) instantiates for its architecture,
// written once over xsimd's Arch: the unit picks the ones its ISA has a form of its own for and puts
// them in its tables. Included only by those units (each Arch is instantiated in one of them).
#include <cstdint>

#include "common/triangle_kernels_impl.hpp"
#include "common/watertight_packet_impl.hpp"
#include "kdtree/packet/block_meeting_impl.hpp"
#include "kdtree/packet/lane_box_test_impl.hpp"
#include "kdtree/packet/one_origin_frustum_impl.hpp"
#include "kdtree/packet/packet_kernels.hpp"
#include "kdtree/packet/packet_lanes_impl.hpp"
#include "kdtree/packet/packet_set_ranges_impl.hpp"
#include "simd/lane_bits.hpp"
#include "vlf/stream/packet_lookup_impl.hpp"
#include "vlf/vlf_kernels.hpp"

namespace beamtrace::simd {

template <class Arch>
struct UnitKernels {
    // One ray against up to one register of triangles.
    static void ray_one_register(const WatertightRay& r, const Triangle* const* tris, int n, LaneHits& out) {
        out.mask = 0;
        ray_xw<Arch>(r, tris, n, out, 0);
    }
    static void packet_one_triangle(const WatertightPacket16& p, const Triangle& tri, LaneHits& out) {
        packet_x1<Arch>(p, tri, out);
    }
    static void ray_corner_rows(const WatertightRay& r, const float* rows, std::size_t stride, std::size_t first, int n,
                                LaneHits& out) {
        ray_rows<Arch>(r, rows, stride, first, n, out);
    }
    static std::uint32_t frustum_cull(const kdtree::OneOriginFrustum& f, const kdtree::CornerRows& rows,
                                      std::size_t first, int n) {
        return kdtree::simd_impl::frustum_misses<Arch>(f, rows, first, n);
    }
    static std::uint32_t lane_box(const kdtree::LaneBoxRays& s, const float* tfar, std::uint32_t lanes,
                                  const Box& box) {
        return kdtree::simd_impl::lanes_meeting<Arch>(s, tfar, lanes, box);
    }
    static void lookup_packet(const vlf::LookupTables& t, const Packet16& p, vlf::PacketLookup& out, bool first_tiles) {
        vlf::lookup_packet_simd<Arch>(t, p, out, first_tiles);
    }
    // A packet's set-up, W lanes a step.
    static constexpr kdtree::PacketSetupKernels packet_setup() {
        return {kdtree::simd_impl::packet_lanes<Arch>,     kdtree::simd_impl::group_ranges<Arch>,
                kdtree::simd_impl::enter_cell<Arch>,       kdtree::simd_impl::farthest_distance<Arch>,
                kdtree::simd_impl::make_one_origin_frustum<Arch>, beamtrace::simd_impl::make_watertight_packet<Arch>,
                kdtree::simd_impl::make_lane_box_rays<Arch>, kdtree::simd_impl::packet_set_ranges<Arch>};
    }
    // Every ISA's table of packet traversal kernels has its own forms.
    static constexpr kdtree::PacketKernels packet_kernels(Isa isa) {
        return {isa, frustum_cull, lane_box, packet_setup(), kdtree::simd_impl::block_meeting<Arch>};
    }
};

}  // namespace beamtrace::simd
