#pragma once
// A packet's bounds in interval traversal (MLRTA section 3.3): the ranges of its rays' origins and
// reciprocal directions per axis, from which every plane interval and test (2) against a box are
// derived. `packet_misses_box` is test (2) for one packet (the scalar reference);
// `PacketKernels::block_meeting` is the same test for every packet of a block traced together,
// 4, 8 or 16 packets per instruction (block_meeting_impl.hpp), with the same operations in the
// same order: its decisions are the reference's, bit for bit.
#include <cstdint>

#include "beamtrace/ray.hpp"
#include "common/interval.hpp"

namespace beamtrace::kdtree {

struct PacketBounds {
    Interval org[3];
    Interval inv[3];
    int sign[3];
    float pad;

    // Range of t at which the active rays cross the plane x_k = p, widened outwards.
    Interval plane_t(int k, float p) const {
        const Interval offset = widen({p - org[k].hi, p - org[k].lo}, pad);
        return widen(offset * inv[k], pad);
    }
    // The same at the face of `box` on axis k where the rays enter its slab, and where they leave it.
    Interval entry_t(const Box& box, int k) const { return plane_t(k, sign[k] > 0 ? box.lower[k] : box.upper[k]); }
    Interval exit_t(const Box& box, int k) const { return plane_t(k, sign[k] > 0 ? box.upper[k] : box.lower[k]); }
};

// Test (2) of section 3.3 for the packet against a box, limited to parameters in [t0, t1].
inline bool packet_misses_box(const PacketBounds& pb, const Box& box, float t0, float t1) {
    Interval entry[3], exit[3];
    for (int k = 0; k < 3; ++k) {
        entry[k] = pb.entry_t(box, k);
        exit[k] = pb.exit_t(box, k);
        if (exit[k].hi < t0 || entry[k].lo > t1) return true;
    }
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            if (a != b && entry[a].lo > exit[b].hi) return true;
    return false;
}

// The bounds of up to 16 packets of one sign octant, one packet per column (structure of arrays),
// and how far each still looks (t1 of test (2)). Unused columns hold empty bounds.
struct alignas(64) BlockBounds {
    static constexpr int kPackets = 16;
    float org_lo[3][kPackets], org_hi[3][kPackets], inv_lo[3][kPackets], inv_hi[3][kPackets];
    float reach[kPackets];
    int sign[3] = {1, 1, 1};
    float pad = 0.0f;
    int count = 0;

    // Puts packet p's bounds (sign and pad are the block's) in column p.
    void set(int p, const PacketBounds& b, float packet_reach);
    // Column p's bounds as set.
    PacketBounds bounds(int p) const;
};

// Bit p set when packet p of [0, block.count) does not miss the box by test (2) with t1 =
// block.reach[p]: !packet_misses_box(block.bounds(p), box, t0, block.reach[p]). The kernel tables'
// block_meeting (kdtree/packet/packet_kernels.hpp); this is the scalar table's reference.
using BlockMeetingKernel = std::uint32_t (*)(const BlockBounds& block, const Box& box, float t0);
std::uint32_t block_meeting_reference(const BlockBounds& block, const Box& box, float t0);

}  // namespace beamtrace::kdtree
