#pragma once
// The SIMD lane policy of the wide BVH's traversal (wide_bvh_traversal.hpp) for one xsimd Arch:
// the children's slab distances a register at a time (kWidth / 16 AVX-512 registers, / 8 AVX2, / 4
// SSE4.2), the leaf by ray_rows. Included only by the per-ISA units (simd/kernels_<isa>.cpp).
#include <immintrin.h>

#include <xsimd/xsimd.hpp>

#include "bvh/wide_bvh_traversal.hpp"
#include "common/triangle_kernels_impl.hpp"
#include "simd/lane_bits.hpp"

namespace beamtrace::bvh {

template <class Arch>
struct SimdLanes {
    using B = xsimd::batch<float, Arch>;
    static constexpr int kLanes = int(B::size);  // children per register
    static_assert(kWidth % kLanes == 0);

    struct Prepared {
        B org[3], inv[3], inv_near[3], inv_far[3];
        std::size_t near[3], far[3];  // offsets (floats) of the near and far planes' rows in a node
    };
    static Prepared prepare(const BoxRay& r) {
        Prepared p;
        for (int a = 0; a < 3; ++a) {
            p.org[a] = B(r.org[a]);
            p.inv[a] = B(r.inv[a]);
            p.inv_near[a] = B(r.inv_near[a]);
            p.inv_far[a] = B(r.inv_far[a]);
            const std::size_t lower = std::size_t(a) * kWidth, upper = std::size_t(3 + a) * kWidth;
            p.near[a] = r.upper_first[a] ? upper : lower;
            p.far[a] = r.upper_first[a] ? lower : upper;
        }
        return p;
    }

    // ScalarLanes::node's operations, kLanes children at a time (xsimd::max(a, b) and min(a, b) are
    // the instructions whose NaN rule the reference's comparisons copy).
    template <bool kForward>
    static std::uint32_t node(const Prepared& r, const WideNode& n, int children, float tnear, float tfar,
                              float* dist) {
        std::uint32_t bits = 0;
        const float* planes = &n.lower[0][0];
        for (int base = 0; base < children; base += kLanes) {
            B t0[3], t1[3];
            for (int a = 0; a < 3; ++a) {
                const B near_plane = B::load_aligned(planes + r.near[a] + base);
                const B far_plane = B::load_aligned(planes + r.far[a] + base);
                t0[a] = (near_plane - r.org[a]) * (kForward ? r.inv_near[a] : r.inv[a]);
                t1[a] = (far_plane - r.org[a]) * (kForward ? r.inv_far[a] : r.inv[a]);
            }
            const B t_start(kForward ? tnear * kEntryScale : tnear), t_end(kForward ? tfar * kExitScale : tfar);
            B tn = xsimd::max(xsimd::max(t0[0], t0[1]), xsimd::max(t0[2], t_start));
            B tf = xsimd::min(xsimd::min(t1[0], t1[1]), xsimd::min(t1[2], t_end));
            if constexpr (!kForward) {
                tn = tn - xsimd::abs(tn) * B(kBoxSlack);
                tf = tf + xsimd::abs(tf) * B(kBoxSlack);
            }
            tn.store_aligned(dist + base);
            bits |= simd::lane_bits<Arch>(tn <= tf) << base;
        }
        return bits;
    }

    static void leaf(const WatertightRay& w, const float* rows, std::size_t stride, std::uint32_t first, int count,
                     LaneHits& out) {
        simd::ray_rows<Arch>(w, rows, stride, first, count, out);
    }

    // ScalarLanes::leaves: on AVX-512 both blocks in one register a row (the first leaf's row by a
    // masked load, the second's expanded into the lanes behind it), one test; elsewhere one a leaf.
    static void leaves(const WatertightRay& w, const float* rows, int count, const float* rows_b, int count_b,
                       LaneHits& out) {
        if constexpr (kLanes == 16) {
            const __mmask16 a_lanes = __mmask16((1u << count) - 1u);
            const __mmask16 b_lanes = __mmask16(((1u << count_b) - 1u) << count);
            const float* o = &w.org.x;
            const int axis[3] = {w.kx, w.ky, w.kz};
            const simd::Corners<Arch> k = simd::make_corners<Arch>([&](int c, int slot) {
                const std::size_t row = std::size_t(3 * c + axis[slot]);
                const __m512 a = _mm512_maskz_loadu_ps(a_lanes, rows + row * std::size_t(count));
                return B(_mm512_mask_expandloadu_ps(a, b_lanes, rows_b + row * std::size_t(count_b))) -
                       B(o[axis[slot]]);
            });
            out.mask = simd::watertight_core<Arch>(k, B(w.sx), B(w.sy), B(w.sz), B(w.tnear), B(w.tfar),
                                                   (1u << (count + count_b)) - 1u, out, 0);
        } else {
            join_leaves(w, rows, count, rows_b, count_b, out, leaf);
        }
    }
};

}  // namespace beamtrace::bvh
