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

    // The interval test of packet_node_reference on kLanes boxes (lower, upper per axis).
    [[gnu::always_inline]] static std::uint32_t interval_bits(const PacketBounds& b, const B* lower, const B* upper) {
        B entry(b.tnear), exit(b.tfar);
        for (int a = 0; a < 3; ++a) {
            const B& near_plane = b.upper_first[a] ? upper[a] : lower[a];
            const B& far_plane = b.upper_first[a] ? lower[a] : upper[a];
            const B lo(b.inv_lo[a]), hi(b.inv_hi[a]);
            const B n0 = near_plane - B(b.org_hi[a]), n1 = near_plane - B(b.org_lo[a]);
            const B f0 = far_plane - B(b.org_hi[a]), f1 = far_plane - B(b.org_lo[a]);
            const B near_min = xsimd::min(xsimd::min(n0 * lo, n0 * hi), xsimd::min(n1 * lo, n1 * hi));
            const B far_max = xsimd::max(xsimd::max(f0 * lo, f0 * hi), xsimd::max(f1 * lo, f1 * hi));
            entry = xsimd::max(entry, near_min);
            exit = xsimd::min(exit, far_max);
        }
        const B slack(kBoxSlack);
        return simd::lane_bits<Arch>(entry - xsimd::abs(entry) * slack <= exit + xsimd::abs(exit) * slack);
    }

    // packet_node_reference's operations, kLanes children at a time.
    static std::uint32_t packet_node(const PacketBounds& b, const WideNode& n, int children) {
        std::uint32_t bits = 0;
        const float* planes = &n.lower[0][0];
        for (int base = 0; base < children; base += kLanes) {
            B lower[3], upper[3];
            for (int a = 0; a < 3; ++a) {
                lower[a] = B::load_aligned(planes + std::size_t(a) * kWidth + base);
                upper[a] = B::load_aligned(planes + std::size_t(3 + a) * kWidth + base);
            }
            bits |= interval_bits(b, lower, upper) << base;
        }
        return bits;
    }

    // packet_leaf_reference: the boxes of a leaf's triangles (count <= 16, its corner block) by the
    // same test; on AVX-512 one register (masked loads), elsewhere through a node of their boxes.
    static std::uint32_t packet_leaf(const PacketBounds& b, const float* block, int count) {
        if constexpr (kLanes == 16) {
            const __mmask16 lanes = __mmask16((1u << count) - 1u);
            B lower[3], upper[3];
            for (int a = 0; a < 3; ++a) {
                const B c0(_mm512_maskz_loadu_ps(lanes, block + std::size_t(a) * std::size_t(count)));
                const B c1(_mm512_maskz_loadu_ps(lanes, block + std::size_t(3 + a) * std::size_t(count)));
                const B c2(_mm512_maskz_loadu_ps(lanes, block + std::size_t(6 + a) * std::size_t(count)));
                lower[a] = xsimd::min(xsimd::min(c0, c1), c2);
                upper[a] = xsimd::max(xsimd::max(c0, c1), c2);
            }
            return interval_bits(b, lower, upper) & ((1u << count) - 1u);
        } else {
            return packet_leaf_reference(b, block, count);
        }
    }

    // packet_bounds_reference: on AVX-512 the 16 lanes in one register each (lanes not in `lanes`
    // take the first live lane's values, then reductions), elsewhere the reference.
    static bool packet_bounds(const Packet16& p, std::uint32_t lanes, const float* const inv[3], PacketBounds& b) {
        if constexpr (kLanes == 16) {
            if (lanes == 0) return false;
            const __mmask16 live = __mmask16(lanes);
            const __m512i first = _mm512_set1_epi32(__builtin_ctz(lanes));
            // Dead lanes take the first live lane's value: no minimum or maximum changes.
            const auto load = [&](const float* v) {
                const __m512 x = _mm512_loadu_ps(v);
                return B(_mm512_mask_blend_ps(live, _mm512_permutexvar_ps(first, x), x));
            };
            const auto lowest = [](const B& x) { return _mm512_reduce_min_ps(x); };
            const auto highest = [](const B& x) { return _mm512_reduce_max_ps(x); };
            const B tn = load(p.tnear), tf = load(p.tfar);
            PacketBounds f, r;
            f.tnear = lowest(tn);
            f.tfar = highest(tf);
            r.tnear = 0.0f;
            r.tfar = highest((tf - tn) * B(1.0f + kBoxSlack));
            bool finite = std::isfinite(r.tfar);
            const float* org[3] = {p.org_x, p.org_y, p.org_z};
            const float* dir[3] = {p.dir_x, p.dir_y, p.dir_z};
            for (int a = 0; a < 3; ++a) {
                const B v = load(inv[a]), o = load(org[a]), d = load(dir[a]);
                const B step = tf * d;
                const B end = o + step;
                const B err = (xsimd::abs(o) + B(2.0f) * xsimd::abs(step)) * B(1.0f / 4194304.0f);
                if (!set_axis_bounds(a, lowest(v), highest(v), lowest(o), highest(o), lowest(end - err),
                                     highest(end + err), f, r, finite))
                    return false;
            }
            b = tighter_bounds(f, r, finite);
            return true;
        } else {
            return packet_bounds_reference(p, lanes, inv, b);
        }
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
