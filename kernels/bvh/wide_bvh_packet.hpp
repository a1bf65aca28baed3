#pragma once
// Occlusion of a coherent packet of 16 rays (shadow rays of a 4x4 pixel block towards a light, 16
// sorted neighbours through one light) through the wide BVH, the packet walking together: beyond
// the papers this project follows (MLRTA traces shadows through its kd-tree; docs/mlrta.md, "Shadow
// packets through a wide BVH").
//
// The packet's interval bounds: per axis the range of the origins and of the reciprocal directions
// (one sign for every ray), of the rays as given or from their far ends back, whichever spreads its
// origins less. A node's children are tested against them (the paper's test (2) in interval
// arithmetic, 32 boxes at once), and each child they admit against each live ray
// (kdtree::PacketKernels::lane_box): it is pushed with the rays that meet it. At a leaf its
// triangles' boxes are tested against the bounds, and the admitted triangles against the leaf's
// rays, 16 lanes a triangle (TriangleKernels::packet_x1, the watertight test every engine uses). The
// box tests only ever keep too much, never too little, so a ray is occluded exactly when its
// single-ray walk says so. Lanes whose directions differ in sign go octant by octant (four or more
// together), the others, and lanes with a zero or infinite reciprocal, ray by ray.
#include <cmath>
#include <cstdint>

#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "bvh/wide_bvh.hpp"

namespace beamtrace::bvh {

// The interval bounds of a packet's live rays: per axis the origins' and the reciprocal
// directions' ranges (the reciprocals all of one sign; upper_first when negative), the smallest
// start and the largest end of the segments.
struct PacketBounds {
    float org_lo[3], org_hi[3], inv_lo[3], inv_hi[3];
    bool upper_first[3];
    float tnear = 0, tfar = 0;
};

// The bounds of the rays org + t dir, t in [tnear, tfar], or of the same rays from their far ends
// back (e - s dir, s in [0, tfar - tnear], the ends widened by far more than their rounding), the
// one whose origins spread less: shadow rays towards a light share their far end. inv: the lanes'
// reciprocal directions (kdtree::LaneBoxRays::inv). False when the lanes cannot be bounded so (a
// sign differs, a component is 0 or not finite). The reference of WideBvhKernels::packet_bounds (the
// same values: minima and maxima are exact, each lane's end and widening the same operations).
bool packet_bounds_reference(const Packet16& p, std::uint32_t lanes, const float* const inv[3], PacketBounds& out);

// The forward (f) and reversed (r) bounds' axis a from the lanes' extremes: reciprocals [ilo, ihi],
// origins [olo, ohi], widened far ends [elo, ehi]. False when the reciprocals are not all of one
// sign and finite; `finite` becomes false when a far end is not finite.
inline bool set_axis_bounds(int a, float ilo, float ihi, float olo, float ohi, float elo, float ehi, PacketBounds& f,
                            PacketBounds& r, bool& finite) {
    if (!(std::isfinite(ilo) && std::isfinite(ihi) && (ilo > 0.0f || ihi < 0.0f))) return false;
    f.upper_first[a] = ihi < 0.0f;
    r.upper_first[a] = !f.upper_first[a];
    f.inv_lo[a] = ilo;
    f.inv_hi[a] = ihi;
    r.inv_lo[a] = -ihi;  // the reversed rays' reciprocals: the negated ones (exact), mirrored
    r.inv_hi[a] = -ilo;
    f.org_lo[a] = olo;
    f.org_hi[a] = ohi;
    r.org_lo[a] = elo;
    r.org_hi[a] = ehi;
    finite = finite && std::isfinite(elo) && std::isfinite(ehi);
    return true;
}

// The reversed bounds when their ends are finite and spread less than the origins, else the forward.
inline const PacketBounds& tighter_bounds(const PacketBounds& f, const PacketBounds& r, bool finite) {
    const auto spread = [](const PacketBounds& q) {
        return (q.org_hi[0] - q.org_lo[0]) + (q.org_hi[1] - q.org_lo[1]) + (q.org_hi[2] - q.org_lo[2]);
    };
    return finite && spread(r) < spread(f) ? r : f;
}

// Bit c set when child c (< children) of the node may meet a ray the bounds hold: per axis the
// near and far distances' extremes over the four corners of (plane - origin range) x (reciprocal
// range), entry the largest near extreme and tnear, exit the smallest far extreme and tfar, kept
// when entry - |entry| kBoxSlack <= exit + |exit| kBoxSlack. The reference of
// WideBvhKernels::packet_node (the same operations in the same order).
std::uint32_t packet_node_reference(const PacketBounds& b, const WideNode& n, int children);

// Bit i set when triangle i of a leaf (its corner block of count <= 16 triangles) has a box the
// bounds may meet: packet_node_reference's test on the triangles' boxes. The reference of
// WideBvhKernels::packet_leaf.
std::uint32_t packet_leaf_reference(const PacketBounds& b, const float* block, int count);

// Bit i set when active ray i of the packet is occluded: the answers of occluded() ray by ray, by the
// kernels of `isa`. counters (may be null) count packets, packet_steps (inner nodes), leaves and
// triangle tests (a packet and a triangle); lanes of a packet that cannot be bounded go ray by ray
// (single_rays, and the single-ray walk's own counts).
std::uint32_t occluded_packet(const WideBvh& bvh, const Packet16& packet, Isa isa, QueryCounters* counters = nullptr);

}  // namespace beamtrace::bvh
