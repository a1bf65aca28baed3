#pragma once
// LaneBoxRays::meets written once over xsimd batches, W lanes per step, and the set-up of the
// LaneBoxRays (make_lane_box_rays: copies and reciprocals, each the same division). Included only by
// the per-ISA units.
#include <xsimd/xsimd.hpp>

#include "simd/lane_bits.hpp"
#include "kdtree/packet/lane_box_test.hpp"

namespace beamtrace::kdtree::simd_impl {

template <class Arch>
std::uint32_t lanes_meeting(const LaneBoxRays& s, const float* tfar, std::uint32_t lanes, const Box& box) {
    using B = xsimd::batch<float, Arch>;
    constexpr int W = int(B::size);
    const B rel(kRelativePad);
    B lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = B(box.lower[k] - s.pad);
        hi[k] = B(box.upper[k] + s.pad);
    }
    std::uint32_t out = 0;
    for (int base = 0; base < 16; base += W) {
        if (((lanes >> base) & ((1u << W) - 1u)) == 0) continue;
        B t0 = B::load_aligned(s.tnear + base), t1 = B::load_unaligned(tfar + base);
        for (int k = 0; k < 3; ++k) {
            const B o = B::load_aligned(s.org[k] + base), inv = B::load_aligned(s.inv[k] + base);
            const B a = (lo[k] - o) * inv, b = (hi[k] - o) * inv;
            // std::min(a, b) is (b < a) ? b : a, and std::max(a, b) is (a < b) ? b : a: the same
            // selects, so NaN-free inputs give the reference's values bit for bit.
            t0 = xsimd::max(t0, xsimd::select(b < a, b, a));
            t1 = xsimd::min(t1, xsimd::select(a < b, b, a));
        }
        const auto meets = (t0 - xsimd::abs(t0) * rel) <= (t1 + xsimd::abs(t1) * rel);
        out |= beamtrace::simd::lane_bits<Arch>(meets) << base;
    }
    return out & lanes;
}

template <class Arch>
void make_lane_box_rays(const Packet16& packet, float pad, LaneBoxRays& s) {
    using B = xsimd::batch<float, Arch>;
    const float* org[3] = {packet.org_x, packet.org_y, packet.org_z};
    const float* dir[3] = {packet.dir_x, packet.dir_y, packet.dir_z};
    for (int base = 0; base < 16; base += int(B::size)) {
        for (int k = 0; k < 3; ++k) {
            B::load_unaligned(org[k] + base).store_aligned(s.org[k] + base);
            (B(1.0f) / B::load_unaligned(dir[k] + base)).store_aligned(s.inv[k] + base);
        }
        B::load_unaligned(packet.tnear + base).store_aligned(s.tnear + base);
    }
    s.pad = pad;
}

}  // namespace beamtrace::kdtree::simd_impl
