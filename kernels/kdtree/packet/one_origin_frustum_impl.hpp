#pragma once
// OneOriginFrustum::misses written once over xsimd batches, W triangles per step, their corners
// loaded from the tree's corner rows (one plain load per coordinate). Included only by the per-ISA
// units.
#include <cstddef>

#include <xsimd/xsimd.hpp>

#include "simd/lane_bits.hpp"
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

}  // namespace beamtrace::kdtree::simd_impl
