#pragma once
// The per-packet arithmetic of interval traversal (packet_lanes.hpp: lane classes and validity, group
// ranges, the farthest distance, the cut to the start cell) written once over xsimd batches, W lanes
// a step (4 with SSE4.2, 8 with AVX2, 16 with AVX-512). Every lane repeats the SSE reference's
// operations in the same order (contraction is off), and the folds over lanes take them in the
// reference's order (simd/lane_folds.hpp), so every result is the reference's, bit for bit.
// Included only by the per-ISA units.
#include <cfloat>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "common/ray_validity_impl.hpp"
#include "kdtree/packet/packet_lanes.hpp"
#include "simd/lane_bits.hpp"
#include "simd/lane_folds.hpp"

namespace beamtrace::kdtree::simd_impl {

// The bits of a register's lanes in a lane word.
template <class B>
constexpr std::uint32_t kRegisterLanes = (1u << B::size) - 1u;

// packet_lanes, segment_lanes (ray_validity.hpp) in the same pass.
template <class Arch>
void packet_lanes(const Packet16& p, PacketLanes& l) {
    using B = xsimd::batch<float, Arch>;
    using beamtrace::simd::lane_bits;
    using beamtrace::simd::sign_bits;
    constexpr int W = int(B::size);
    std::uint32_t segment = 0, flat = 0, negative[3] = {0, 0, 0};
    const B tiny(FLT_MIN), zero(0.0f), one(1.0f);
    for (int base = 0; base < 16; base += W) {
        const B ox = B::load_unaligned(p.org_x + base), oy = B::load_unaligned(p.org_y + base),
                oz = B::load_unaligned(p.org_z + base);
        const B dx = B::load_unaligned(p.dir_x + base), dy = B::load_unaligned(p.dir_y + base),
                dz = B::load_unaligned(p.dir_z + base);
        const B tnear = B::load_unaligned(p.tnear + base), tfar = B::load_unaligned(p.tfar + base);
        segment |= lane_bits<Arch>(beamtrace::simd::describes_segment_lanes<Arch>(ox, oy, oz, dx, dy, dz, tnear, tfar))
                   << base;
        const B speed = xsimd::sqrt(dx * dx + dy * dy + dz * dz), inv = one / speed;
        speed.store_aligned(l.speed + base);
        (dx * inv).store_aligned(l.unit[0] + base);
        (dy * inv).store_aligned(l.unit[1] + base);
        (dz * inv).store_aligned(l.unit[2] + base);
        // Not >= FLT_MIN (NaN included): no usable reciprocal.
        const auto usable = (xsimd::abs(dx) >= tiny) & (xsimd::abs(dy) >= tiny) & (xsimd::abs(dz) >= tiny);
        flat |= (~lane_bits<Arch>(usable) & kRegisterLanes<B>) << base;
        negative[0] |= sign_bits<Arch>(dx) << base;
        negative[1] |= sign_bits<Arch>(dy) << base;
        negative[2] |= sign_bits<Arch>(dz) << base;
    }
    l.valid = p.active & 0xFFFFu & segment;
    l.flat = flat & l.valid;
    for (int k = 0; k < 3; ++k) l.negative[k] = negative[k];
}

template <class Arch>
GroupRanges group_ranges(const Packet16& p, const PacketLanes& l, std::uint32_t lanes) {
    using B = xsimd::batch<float, Arch>;
    constexpr int W = int(B::size);
    const float* v[6] = {p.org_x, p.org_y, p.org_z, l.unit[0], l.unit[1], l.unit[2]};
    beamtrace::simd::MinFold lo[6];
    beamtrace::simd::MaxFold hi[6];
    for (int base = 0; base < 16; base += W) {
        const std::uint32_t bits = (lanes >> base) & kRegisterLanes<B>;
        if (bits == 0) continue;
        const auto on = beamtrace::simd::lanes_on<Arch>(bits);
        for (int k = 0; k < 6; ++k) {
            const B x = B::load_unaligned(v[k] + base);
            if (bits == kRegisterLanes<B>) {  // the same values without the selects
                lo[k].add(x);
                hi[k].add(x);
            } else {
                lo[k].add(x, on);
                hi[k].add(x, on);
            }
        }
    }
    GroupRanges g;
    for (int k = 0; k < 3; ++k) {
        g.org[k] = {lo[k].result(), hi[k].result()};
        g.unit[k] = {lo[k + 3].result(), hi[k + 3].result()};
    }
    return g;
}

template <class Arch>
float farthest_distance(const float* tfar, const float* speed, std::uint32_t lanes) {
    using B = xsimd::batch<float, Arch>;
    constexpr int W = int(B::size);
    beamtrace::simd::MaxFold far;
    for (int base = 0; base < 16; base += W) {
        const std::uint32_t bits = (lanes >> base) & kRegisterLanes<B>;
        if (bits == 0) continue;
        far.add(B::load_unaligned(tfar + base) * B::load_unaligned(speed + base),
                beamtrace::simd::lanes_on<Arch>(bits));
    }
    return far.result();
}

template <class Arch>
CellEntry enter_cell(const Packet16& p, std::uint32_t lanes, const float* speed, const Box& box, float pad) {
    using B = xsimd::batch<float, Arch>;
    using beamtrace::simd::max_as_std;
    using beamtrace::simd::min_as_std;
    constexpr int W = int(B::size);
    const float* org[3] = {p.org_x, p.org_y, p.org_z};
    const float* dir[3] = {p.dir_x, p.dir_y, p.dir_z};
    const B rel(kRelativePad), pad_b(pad);
    beamtrace::simd::MinFold c0, near, org_lo[3], inv_lo[3];
    beamtrace::simd::MaxFold c1, org_hi[3], inv_hi[3];
    std::uint32_t kept = 0;
    for (int base = 0; base < 16; base += W) {
        const std::uint32_t bits = (lanes >> base) & kRegisterLanes<B>;
        if (bits == 0) continue;
        const auto on = beamtrace::simd::lanes_on<Arch>(bits);
        const bool all_on = bits == kRegisterLanes<B>;
        const B s = B::load_aligned(speed + base);
        const B tnear = B::load_unaligned(p.tnear + base) * s;
        B enter = tnear, exit = B::load_unaligned(p.tfar + base) * s;
        for (int k = 0; k < 3; ++k) {
            const B o = B::load_unaligned(org[k] + base);
            const B inv = s / B::load_unaligned(dir[k] + base);  // reciprocal of the unit direction's component
            const B a = (B(box.lower[k]) - o) * inv, b = (B(box.upper[k]) - o) * inv;
            const auto swap = a > b;
            enter = max_as_std(enter, xsimd::select(swap, b, a));
            exit = min_as_std(exit, xsimd::select(swap, a, b));
            if (all_on) {  // the same values without the selects
                org_lo[k].add(o);
                org_hi[k].add(o);
                inv_lo[k].add(inv);
                inv_hi[k].add(inv);
            } else {
                org_lo[k].add(o, on);
                org_hi[k].add(o, on);
                inv_lo[k].add(inv, on);
                inv_hi[k].add(inv, on);
            }
        }
        // Rounding of enter / exit is covered by widening the packet's interval afterwards.
        const B slack = (xsimd::abs(enter) + xsimd::abs(exit)) * rel + pad_b;
        const auto in = on & !(enter > exit + slack);
        kept |= beamtrace::simd::lane_bits<Arch>(in) << base;
        c0.add(enter, in);
        c1.add(exit, in);
        near.add(tnear, in);
    }
    CellEntry e;
    e.lanes = kept;
    e.c0 = c0.result();
    e.c1 = c1.result();
    e.near = near.result();
    for (int k = 0; k < 3; ++k) {
        e.org[k] = {org_lo[k].result(), org_hi[k].result()};
        e.inv[k] = {inv_lo[k].result(), inv_hi[k].result()};
    }
    return e;
}

}  // namespace beamtrace::kdtree::simd_impl
