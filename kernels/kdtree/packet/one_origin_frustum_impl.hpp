#pragma once
// OneOriginFrustum::misses written once over xsimd batches, W triangles per step, their corners
// loaded from the tree's corner rows (one plain load per coordinate); and make_one_origin_frustum, W
// lanes per step, each lane's operations the SSE reference's, the ranges folded in its order
// (simd/lane_folds.hpp): the same frustum, bit for bit. Included only by the per-ISA units.
#include <cstddef>

#include <xsimd/xsimd.hpp>

#include "simd/lane_bits.hpp"
#include "simd/lane_folds.hpp"
#include "kdtree/packet/one_origin_frustum.hpp"

namespace beamtrace::kdtree::simd_impl {

// Bit i set when the frustum misses leaf triangle first + i of `rows` (i < n <= 16). Lanes past n
// load the next triangles or the rows' padding; their bits are dropped.
template <class Arch>
std::uint32_t frustum_misses(const OneOriginFrustum& f, const CornerRows& rows, std::size_t first, int n) {
    using B = xsimd::batch<float, Arch>;
    constexpr int W = int(B::size);
    const int m = f.m, j0 = f.j0, j1 = f.j1;
    const B sm(f.sm), zero(0.0f), one(1.0f), slope_error(OneOriginFrustum::kSlopeError);
    const B om(f.origin[m]), oj0(f.origin[j0]), oj1(f.origin[j1]);
    const B abs_om(std::fabs(f.origin[m])), abs_oj0(std::fabs(f.origin[j0])), abs_oj1(std::fabs(f.origin[j1]));
    const B lo0(f.slope[j0].lo), hi0(f.slope[j0].hi), lo1(f.slope[j1].lo), hi1(f.slope[j1].hi);
    const B reach(f.reach), depth_error(OneOriginFrustum::kDepthError);
    auto coordinate = [&rows, first](int base, int c) {
        return B::load_unaligned(rows.at + std::size_t(c) * rows.stride + first + std::size_t(base));
    };
    std::uint32_t result = 0;
    for (int base = 0; base < n; base += W) {
        // Corner coordinates on the main axis and the two others, one triangle per lane; lanes past
        // n hold whatever the loader gives (their bits are dropped).
        const int live = n - base < W ? n - base : W;
        auto in_front = B(0.0f) == zero;  // all true
        auto below0 = in_front, above0 = in_front, below1 = in_front, above1 = in_front, beyond = in_front;
        for (int v = 0; v < 3; ++v) {
            const B pm = coordinate(base, 3 * v + m);
            const B p0 = coordinate(base, 3 * v + j0);
            const B p1 = coordinate(base, 3 * v + j1);
            const B w = (pm - om) * sm;
            in_front = in_front & (w > zero);
            beyond = beyond & ((w - (xsimd::abs(pm) + abs_om) * depth_error) > reach);
            const B inv_w = one / w;
            const B err = slope_error * inv_w;
            const B depth = xsimd::abs(pm) + abs_om;
            const B q0 = (p0 - oj0) * inv_w, q1 = (p1 - oj1) * inv_w;
            const B e0 = ((xsimd::abs(p0) + abs_oj0) + xsimd::abs(q0) * depth) * err;
            const B e1 = ((xsimd::abs(p1) + abs_oj1) + xsimd::abs(q1) * depth) * err;
            below0 = below0 & ((q0 + e0) < lo0);
            above0 = above0 & ((q0 - e0) > hi0);
            below1 = below1 & ((q1 + e1) < lo1);
            above1 = above1 & ((q1 - e1) > hi1);
        }
        const auto miss = in_front & (below0 | above0 | below1 | above1 | beyond);
        result |= (beamtrace::simd::lane_bits<Arch>(miss) & ((1u << live) - 1u)) << base;
    }
    return result;
}

// make_one_origin_frustum.
template <class Arch>
OneOriginFrustum make_one_origin_frustum(const Packet16& packet, std::uint32_t mask) {
    using B = xsimd::batch<float, Arch>;
    constexpr int W = int(B::size);
    constexpr std::uint32_t kRegister = (1u << W) - 1u;
    OneOriginFrustum f;
    if (mask == 0) return f;
    const float* org[3] = {packet.org_x, packet.org_y, packet.org_z};
    const float* dir[3] = {packet.dir_x, packet.dir_y, packet.dir_z};
    const int first = __builtin_ctz(mask);
    std::uint32_t same = 0;
    for (int base = 0; base < 16; base += W) {
        auto eq = B::load_unaligned(org[0] + base) == B(org[0][first]);
        eq = eq & (B::load_unaligned(org[1] + base) == B(org[1][first]));
        eq = eq & (B::load_unaligned(org[2] + base) == B(org[2][first]));
        same |= beamtrace::simd::lane_bits<Arch>(eq) << base;
    }
    if ((same & mask) != mask) return f;  // several origins: no frustum
    set_frustum_axes(f, packet, first);
    beamtrace::simd::MinFold q_lo[2];
    beamtrace::simd::MaxFold q_hi[2], reach;
    const int js[2] = {f.j0, f.j1};
    for (int base = 0; base < 16; base += W) {
        const std::uint32_t bits = (mask >> base) & kRegister;
        if (bits == 0) continue;
        const auto on = beamtrace::simd::lanes_on<Arch>(bits);
        const B dm = xsimd::abs(B::load_unaligned(dir[f.m] + base));
        for (int a = 0; a < 2; ++a) {
            const B q = B::load_unaligned(dir[js[a]] + base) / dm;
            q_lo[a].add(q, on);
            q_hi[a].add(q, on);
        }
        reach.add(B::load_unaligned(packet.tfar + base) * dm, on);
    }
    finish_frustum(f, {q_lo[0].result(), q_hi[0].result()}, {q_lo[1].result(), q_hi[1].result()}, reach.result());
    return f;
}

}  // namespace beamtrace::kdtree::simd_impl
