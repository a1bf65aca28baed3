#pragma once
// The single-ray traversal of a wide BVH, written once over a lane policy (the box tests of a node's
// eight children and the test of a leaf's triangles): ScalarLanes below is the reference,
// wide_bvh_traversal_impl.hpp the SIMD policies of the per-ISA units. Both make the same operations
// in the same order on the same values, so every policy returns the reference's answer bit for bit.
//
// Front to back with a stack of (child, entry distance): the children a node's boxes admit are
// pushed nearest on top, a leaf's triangles are tested (closest hit: the nearest lane, the first at
// equal t; occlusion: any), an entry farther than the closest hit is skipped.
#include <cmath>
#include <cstdint>

#include "beamtrace/query.hpp"
#include "bvh/wide_bvh.hpp"
#include "common/ray_validity.hpp"
#include "common/triangle_kernels.hpp"
#include "common/triangle_reference.hpp"
#include "common/watertight_ray.hpp"

namespace beamtrace::bvh {

// A box is skipped only when its entry lies beyond its exit by more than this relative slack (the
// kd-tree's, kdtree/ray_traversal.hpp): slab distances and the triangle test's t carry rounding,
// and a triangle on a box's face must never be lost.
constexpr float kBoxSlack = 1.0f / 1048576.0f;

// The per-ray values of the box tests: the origin, the reciprocals of the direction and, per axis,
// whether the upper plane is met first (negative reciprocal, -0 and -inf included).
struct BoxRay {
    float org[3], inv[3];
    bool upper_first[3];
};

inline BoxRay make_box_ray(const Ray& ray) {
    BoxRay b;
    for (int a = 0; a < 3; ++a) {
        b.org[a] = ray.org[a];
        b.inv[a] = 1.0f / ray.dir[a];
        b.upper_first[a] = std::signbit(b.inv[a]);
    }
    return b;
}

// The reference policy. A slab distance is NaN when the origin lies in a plane the ray runs
// along (0 * inf); the running maximum and minimum keep their value then (the comparisons below,
// which are what the SIMD max and min instructions do with a NaN first operand), so such a plane
// never culls.
struct ScalarLanes {
    static const BoxRay& prepare(const BoxRay& r) { return r; }

    // Bit c set when child c's box meets [tnear, tfar]; dist[c] its (slackened) entry distance.
    static std::uint32_t node(const BoxRay& r, const WideNode& n, float tnear, float tfar, float* dist) {
        std::uint32_t bits = 0;
        for (int c = 0; c < kWidth; ++c) {
            float tn = tnear, tf = tfar;
            for (int a = 0; a < 3; ++a) {
                const float near_plane = r.upper_first[a] ? n.upper[a][c] : n.lower[a][c];
                const float far_plane = r.upper_first[a] ? n.lower[a][c] : n.upper[a][c];
                const float t0 = (near_plane - r.org[a]) * r.inv[a];
                const float t1 = (far_plane - r.org[a]) * r.inv[a];
                tn = t0 > tn ? t0 : tn;
                tf = t1 < tf ? t1 : tf;
            }
            tn = tn - std::fabs(tn) * kBoxSlack;
            tf = tf + std::fabs(tf) * kBoxSlack;
            dist[c] = tn;
            if (tn <= tf) bits |= 1u << c;
        }
        return bits;
    }

    // The leaf's triangles first .. first + count - 1 of the rows, as TriangleKernels::ray_rows does.
    static void leaf(const WatertightRay& w, const float* rows, std::size_t stride, std::uint32_t first, int count,
                     LaneHits& out) {
        out.mask = 0;
        for (int i = 0; i < count; ++i) {
            Triangle tri;
            float* v = &tri.v0.x;
            for (int c = 0; c < 9; ++c) v[c] = rows[std::size_t(c) * stride + first + std::uint32_t(i)];
            TriangleHit h;
            if (intersect_triangle(w, tri, h)) {
                out.t[i] = h.t;
                out.u[i] = h.u;
                out.v[i] = h.v;
                out.mask |= 1u << i;
            }
        }
    }
};

template <class Lanes, bool kOcclusion, bool kCount>
Hit traverse_wide(const WideBvh& bvh, const Ray& ray, QueryCounters* counters) {
    if constexpr (kCount) ++counters->rays;
    if (!describes_segment(ray) || bvh.root == kEmpty) return Hit{};
    const BoxRay box_ray = make_box_ray(ray);
    WatertightRay wray = make_watertight_ray(ray);
    const auto prepared = Lanes::prepare(box_ray);

    struct Entry {
        std::uint32_t ref;
        float tnear;
    };
    Entry stack[WideBvh::kMaxDepth * (kWidth - 1) + 1];
    int top = 0;
    Hit best;
    float tfar = ray.tfar;
    std::uint32_t ref = bvh.root;
    for (;;) {
        if (!is_leaf(ref)) {
            if constexpr (kCount) ++counters->inner_steps;
            const WideNode& node = bvh.nodes[ref];
            alignas(64) float dist[16];
            std::uint32_t bits = Lanes::node(prepared, node, ray.tnear, tfar, dist);
            if (bits != 0) {
                int c = __builtin_ctz(bits);
                bits &= bits - 1;
                if (bits == 0) {
                    ref = node.child[c];
                    continue;
                }
                // Several: pushed nearest on top (insertion by entry distance; at equal distance the
                // later child first, the same order for every policy).
                const int base = top;
                stack[top++] = Entry{node.child[c], dist[c]};
                do {
                    c = __builtin_ctz(bits);
                    bits &= bits - 1;
                    const Entry e{node.child[c], dist[c]};
                    int k = top++;
                    while (k > base && stack[k - 1].tnear < e.tnear) {
                        stack[k] = stack[k - 1];
                        --k;
                    }
                    stack[k] = e;
                } while (bits != 0);
                ref = stack[--top].ref;
                continue;
            }
        } else {
            const std::uint32_t first = leaf_first(ref);
            const int count = int(leaf_count(ref));
            if constexpr (kCount) {
                ++counters->leaves;
                counters->triangle_tests += std::uint64_t(count);
            }
            LaneHits lanes;
            Lanes::leaf(wray, bvh.rows.data(), bvh.stride, first, count, lanes);
            if constexpr (kOcclusion) {
                if (lanes.mask != 0) {
                    const int i = __builtin_ctz(lanes.mask);
                    return Hit{lanes.t[i], bvh.triangle_ids[first + std::uint32_t(i)], lanes.u[i], lanes.v[i]};
                }
            } else {
                for (std::uint32_t m = lanes.mask; m != 0; m &= m - 1) {
                    const int i = __builtin_ctz(m);
                    if (lanes.t[i] < best.t)
                        best = Hit{lanes.t[i], bvh.triangle_ids[first + std::uint32_t(i)], lanes.u[i], lanes.v[i]};
                }
                if (best.hit()) tfar = wray.tfar = best.t;
            }
        }
        // The next entry, skipping those that start beyond the closest hit.
        for (;;) {
            if (top == 0) return best;
            const Entry& e = stack[--top];
            if (!kOcclusion && e.tnear > tfar) continue;
            ref = e.ref;
            break;
        }
    }
}

}  // namespace beamtrace::bvh
