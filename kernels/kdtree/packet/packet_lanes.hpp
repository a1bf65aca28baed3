#pragma once
// The per-packet arithmetic of interval traversal for all 16 lanes at once (SSE, the library's
// baseline, four lanes per instruction): direction lengths and lane classes, ranges of a value over
// some lanes, and each lane's segment cut to a cell. Before this the same work ran lane by lane
// and was about half of kd16's time on `room`. These are the references of the set-up kernels
// (packet_setup_kernels.hpp: the same results 8 or 16 lanes a step), which traversal calls.
#include <cstdint>

#include "beamtrace/ray.hpp"
#include "common/interval.hpp"

namespace beamtrace::kdtree {

struct alignas(64) PacketLanes {
    float speed[16];                        // |dir| (any value in lanes outside `valid`)
    float unit[3][16];                      // dir_k * (1 / |dir|)
    std::uint32_t valid = 0;                // active lanes that describe a segment (ray_validity.hpp)
    std::uint32_t flat = 0;                 // valid lanes with a direction component of magnitude below FLT_MIN
    std::uint32_t negative[3] = {0, 0, 0};  // sign bit of dir_k, every lane
};
PacketLanes packet_lanes(const Packet16& p);
void packet_lanes(const Packet16& p, PacketLanes& out);  // the same, in place

// The lanes of `lanes` whose direction has the signs of octant o (bit k set: dir_k negative), from
// the lanes' sign masks per axis (negative[k]: bit i set when lane i's dir_k is negative).
inline std::uint32_t octant_lanes(const std::uint32_t (&negative)[3], std::uint32_t lanes, int o) {
    for (int k = 0; k < 3; ++k) lanes &= ((o >> k) & 1) ? negative[k] : ~negative[k];
    return lanes;
}
inline std::uint32_t octant_lanes(const PacketLanes& l, std::uint32_t lanes, int o) {
    return octant_lanes(l.negative, lanes, o);
}

// Minimum and maximum of v[i] over the lanes i of `lanes` (at least one).
Interval lane_range(const float* v, std::uint32_t lanes);

// The ranges of the origins and of the unit directions (PacketLanes::unit) over the lanes of
// `lanes` (at least one), in one pass: lane_range of each of the six, the same values.
struct GroupRanges {
    Interval org[3], unit[3];
};
GroupRanges group_ranges(const Packet16& p, const PacketLanes& l, std::uint32_t lanes);

// The largest tfar[i] * speed[i] over the lanes (at least one): how far along its line any of them
// still needs to look.
float farthest_distance(const float* tfar, const float* speed, std::uint32_t lanes);

// Interval traversal's start in a cell: each lane's segment in distance along its line,
// [tnear |dir|, tfar |dir|], cut to the box; `lanes` keeps those whose cut is not empty (up to a
// relative 2^-16 and `pad`), c0 / c1 are the hull of their cuts and near the least tnear |dir|.
// org and inv are the ranges of the origins and of |dir| / dir_k over the input lanes.
struct CellEntry {
    std::uint32_t lanes = 0;
    float c0 = 0, c1 = 0, near = 0;
    Interval org[3], inv[3];
};
CellEntry enter_cell(const Packet16& p, std::uint32_t lanes, const float* speed, const Box& box, float pad);

}  // namespace beamtrace::kdtree
