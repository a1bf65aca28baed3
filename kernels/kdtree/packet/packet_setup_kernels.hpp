#pragma once
// The per-packet set-up of interval traversal as kernels of one instruction set (a part of the
// PacketKernels table, packet_kernels.hpp): the lane classes and validity, the group ranges, the cut
// to the start cell, the farthest distance, the one-origin frustum, the watertight packet and the lane
// box rays, the ranges a beam is made of. The scalar table holds the references (packet_lanes.hpp, one_origin_frustum.hpp,
// lane_box_test.hpp: SSE, four lanes per instruction; watertight_ray.hpp: make_watertight_ray lane by
// lane); the SSE4.2, AVX2 and
// AVX-512 tables the same operations 4, 8 and 16 lanes at a time, every result the reference's bit for
// bit (tests/kdtree/packet_setup_kernels_test.cpp).
#include <cstdint>

#include "beamtrace/ray.hpp"
#include "common/interval.hpp"
#include "common/watertight_ray.hpp"
#include "kdtree/packet/lane_box_test.hpp"
#include "kdtree/packet/one_origin_frustum.hpp"
#include "kdtree/packet/packet_lanes.hpp"
#include "kdtree/packet/packet_set_ranges.hpp"

namespace beamtrace::kdtree {

struct PacketSetupKernels {
    void (*lanes)(const Packet16& p, PacketLanes& out);  // packet_lanes
    GroupRanges (*group_ranges)(const Packet16& p, const PacketLanes& l, std::uint32_t lanes);
    CellEntry (*enter_cell)(const Packet16& p, std::uint32_t lanes, const float* speed, const Box& box, float pad);
    float (*farthest_distance)(const float* tfar, const float* speed, std::uint32_t lanes);
    OneOriginFrustum (*frustum)(const Packet16& packet, std::uint32_t mask);  // make_one_origin_frustum
    void (*watertight)(const Packet16& p, WatertightPacket16& out);           // make_watertight_packet
    void (*box_rays)(const Packet16& packet, float pad, LaneBoxRays& out);    // make_lane_box_rays
    PacketSetRangesKernel set_ranges;                                         // packet_set_ranges (a beam's)
};

// The references (the scalar table's set-up).
inline constexpr PacketSetupKernels kReferenceSetup{
    static_cast<void (*)(const Packet16&, PacketLanes&)>(packet_lanes),
    group_ranges,
    enter_cell,
    farthest_distance,
    make_one_origin_frustum,
    [](const Packet16& p, WatertightPacket16& w) { w = make_watertight_packet_reference(p); },
    static_cast<void (*)(const Packet16&, float, LaneBoxRays&)>(make_lane_box_rays),
    packet_set_ranges};

}  // namespace beamtrace::kdtree
