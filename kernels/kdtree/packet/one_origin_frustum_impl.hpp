#pragma once
// OneOriginFrustum::misses written once over xsimd batches, W triangles per step (structure of arrays
// gathered from the leaf's triangles). Included only by the per-ISA units.
#include <type_traits>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

#include "simd/lane_bits.hpp"
#include "kdtree/packet/one_origin_frustum.hpp"

namespace beamtrace::kdtree::simd_impl {

// Coordinate `c` (0..8: corner * 3 + axis) of triangles tris[0 .. live - 1], one per lane; lanes
// from `live` on hold zeros. AVX2 and AVX-512 gather it with the lanes past `live` masked off (no
// load); SSE4.2, which has no gather, copies lane by lane (`lanes` is its scratch). The same
// values either way.
template <class Arch>
xsimd::batch<float, Arch> triangle_coordinate(const Triangle* tris, int live, int c, float* lanes) {
    using B = xsimd::batch<float, Arch>;
    constexpr int W = int(B::size);
    const float* base = &tris[0].v0.x + c;
    constexpr int kStride = int(sizeof(Triangle) / sizeof(float));
    static_assert(sizeof(Triangle) == 9 * sizeof(float), "a triangle is nine packed floats");
    if constexpr (std::is_same_v<Arch, xsimd::avx512bw>) {
        const __m512i index = _mm512_mullo_epi32(
            _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15), _mm512_set1_epi32(kStride));
        const auto on = __mmask16(live >= W ? 0xFFFFu : (1u << live) - 1u);
        return B(_mm512_mask_i32gather_ps(_mm512_setzero_ps(), on, index, base, 4));
    } else if constexpr (std::is_same_v<Arch, xsimd::avx2>) {
        const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        const __m256i index = _mm256_mullo_epi32(lane, _mm256_set1_epi32(kStride));
        const __m256 on = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(live), lane));
        return B(_mm256_mask_i32gather_ps(_mm256_setzero_ps(), base, index, on, 4));
    } else {
        for (int i = 0; i < W; ++i) lanes[i] = i < live ? base[i * kStride] : 0.0f;
        return B::load_unaligned(lanes);
    }
}

// The decisions for n triangles (n <= 16), coordinate c of triangles [base, base + W) from
// coordinate(base, live, c) (lanes from `live` on: any finite value; their bits are dropped).
template <class Arch, class Coordinate>
[[gnu::always_inline]] inline std::uint32_t frustum_decisions(const OneOriginFrustum& f, int n,
                                                              const Coordinate& coordinate) {
    using B = xsimd::batch<float, Arch>;
    constexpr int W = int(B::size);
    const int m = f.m, j0 = f.j0, j1 = f.j1;
    const B sm(f.sm), zero(0.0f), one(1.0f), slope_error(OneOriginFrustum::kSlopeError);
    const B om(f.origin[m]), oj0(f.origin[j0]), oj1(f.origin[j1]);
    const B abs_om(std::fabs(f.origin[m])), abs_oj0(std::fabs(f.origin[j0])), abs_oj1(std::fabs(f.origin[j1]));
    const B lo0(f.slope[j0].lo), hi0(f.slope[j0].hi), lo1(f.slope[j1].lo), hi1(f.slope[j1].hi);
    const B reach(f.reach), depth_error(OneOriginFrustum::kDepthError);
    std::uint32_t result = 0;
    for (int base = 0; base < n; base += W) {
        // Corner coordinates on the main axis and the two others, one triangle per lane; lanes past
        // n hold whatever the loader gives (their bits are dropped).
        const int live = n - base < W ? n - base : W;
        auto in_front = B(0.0f) == zero;  // all true
        auto below0 = in_front, above0 = in_front, below1 = in_front, above1 = in_front, beyond = in_front;
        for (int v = 0; v < 3; ++v) {
            const B pm = coordinate(base, live, 3 * v + m);
            const B p0 = coordinate(base, live, 3 * v + j0);
            const B p1 = coordinate(base, live, 3 * v + j1);
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

// Leaf triangles side by side (gathered: AVX2 and AVX-512 gathers, SSE4.2 copies).
template <class Arch>
std::uint32_t frustum_misses(const OneOriginFrustum& f, const Triangle* tris, int n) {
    return frustum_decisions<Arch>(f, n, [tris](int base, int live, int c) {
        alignas(64) float scratch[xsimd::batch<float, Arch>::size];
        return triangle_coordinate<Arch>(tris + base, live, c, scratch);
    });
}

// Corner rows: one plain load per coordinate (the rows' padding keeps it inside the array).
template <class Arch>
std::uint32_t frustum_misses_rows(const OneOriginFrustum& f, const CornerRows& rows, std::size_t first, int n) {
    return frustum_decisions<Arch>(f, n, [&rows, first](int base, int, int c) {
        return xsimd::batch<float, Arch>::load_unaligned(rows.at + std::size_t(c) * rows.stride + first +
                                                         std::size_t(base));
    });
}

}  // namespace beamtrace::kdtree::simd_impl
