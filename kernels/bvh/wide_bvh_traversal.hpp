#pragma once
// The single-ray traversal of a wide BVH, written once over a lane policy (the box tests of a node's
// 32 children and the test of a leaf's triangles): ScalarLanes below is the reference,
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
#include "bvh/wide_bvh_packet.hpp"
#include "common/ray_validity.hpp"
#include "common/triangle_kernels.hpp"
#include "common/watertight_ray.hpp"

namespace beamtrace::bvh {

// A box is skipped only when its entry lies beyond its exit by more than this relative slack (the
// kd-tree's, kdtree/ray_traversal.hpp): slab distances and the triangle test's t carry rounding,
// and a triangle on a box's face must never be lost.
constexpr float kBoxSlack = 1.0f / 1048576.0f;
constexpr float kEntryScale = 1.0f - kBoxSlack, kExitScale = 1.0f + kBoxSlack;

// The per-ray values of the box tests: the origin, the reciprocals of the direction and, per axis,
// whether the upper plane is met first (negative reciprocal, -0 and -inf included).
struct BoxRay {
    float org[3], inv[3];
    float inv_near[3], inv_far[3];  // inv * kEntryScale, inv * kExitScale (the forward form)
    bool upper_first[3];
};

inline BoxRay make_box_ray(const Ray& ray) {
    BoxRay b;
    for (int a = 0; a < 3; ++a) {
        b.org[a] = ray.org[a];
        b.inv[a] = 1.0f / ray.dir[a];
        b.inv_near[a] = b.inv[a] * kEntryScale;
        b.inv_far[a] = b.inv[a] * kExitScale;
        b.upper_first[a] = std::signbit(b.inv[a]);
    }
    return b;
}

// The slab distances of a child: t = (plane - origin) * reciprocal per plane, entry = the largest of
// the near planes' and the ray's tnear, exit = the smallest of the far planes' and tfar, each as a
// two-level tree max(max(x, y), max(z, tnear)) (a short chain of dependent operations). A distance is
// NaN when the origin lies in a plane the ray runs along (0 * inf): max(a, b) and min(a, b) are
// a > b ? a : b and a < b ? a : b, what the SIMD max and min instructions do (a NaN first operand
// gives the second, a NaN second operand is kept and then dropped by the outer level, whose second
// operand is never NaN), so a NaN distance only ever drops a constraint: no box is culled by it.
// The slack: for a ray with tnear >= 0 (kForward) the distances are taken with the reciprocals
// scaled by 1 - s (near planes) and 1 + s (far planes) and tnear, tfar scaled the same way: every
// entry at or beyond 0 is then below the true one and every exit at or beyond 0 above it (the
// roundings are far below s), and an entry below 0 never decides the largest entry, which is at
// least tnear * (1 - s) >= 0 (an exit below 0 fails the test, as the box is behind the ray);
// otherwise entry - |entry| s <= exit + |exit| s on the unscaled distances.
inline float max_keeping(float a, float b) { return a > b ? a : b; }
inline float min_keeping(float a, float b) { return a < b ? a : b; }

// Two leaves' tests as one LaneHits by a one-leaf test `leaf` (ScalarLanes::leaves; the SIMD
// policies' form where one register cannot take both): each block alone, the second's lanes moved up
// behind the first's.
template <class Leaf>
void join_leaves(const WatertightRay& w, const float* rows, int count, const float* rows_b, int count_b, LaneHits& out,
                 const Leaf& leaf) {
    leaf(w, rows, std::size_t(count), 0, count, out);
    LaneHits b;
    leaf(w, rows_b, std::size_t(count_b), 0, count_b, b);
    for (int i = 0; i < count_b; ++i) {
        out.t[count + i] = b.t[i];
        out.u[count + i] = b.u[i];
        out.v[count + i] = b.v[i];
    }
    out.mask |= b.mask << count;
}

// The reference policy.
struct ScalarLanes {
    using Prepared = BoxRay;
    static std::uint32_t packet_node(const PacketBounds& b, const WideNode& n, int children) {
        return packet_node_reference(b, n, children);
    }
    static std::uint32_t packet_leaf(const PacketBounds& b, const float* block, int count) {
        return packet_leaf_reference(b, block, count);
    }
    static bool packet_bounds(const Packet16& p, std::uint32_t lanes, const float* const inv[3], PacketBounds& b) {
        return packet_bounds_reference(p, lanes, inv, b);
    }
    static BoxRay prepare(const BoxRay& r) { return r; }

    // Bit c set when child c (< children, the node's count) meets [tnear, tfar]; dist[c] its
    // (slackened) entry distance.
    template <bool kForward>
    static std::uint32_t node(const BoxRay& r, const WideNode& n, int children, float tnear, float tfar, float* dist) {
        std::uint32_t bits = 0;
        for (int c = 0; c < children; ++c) {
            float t0[3], t1[3];
            for (int a = 0; a < 3; ++a) {
                const float near_plane = r.upper_first[a] ? n.upper[a][c] : n.lower[a][c];
                const float far_plane = r.upper_first[a] ? n.lower[a][c] : n.upper[a][c];
                t0[a] = (near_plane - r.org[a]) * (kForward ? r.inv_near[a] : r.inv[a]);
                t1[a] = (far_plane - r.org[a]) * (kForward ? r.inv_far[a] : r.inv[a]);
            }
            const float t_start = kForward ? tnear * kEntryScale : tnear;
            const float t_end = kForward ? tfar * kExitScale : tfar;
            float tn = max_keeping(max_keeping(t0[0], t0[1]), max_keeping(t0[2], t_start));
            float tf = min_keeping(min_keeping(t1[0], t1[1]), min_keeping(t1[2], t_end));
            if constexpr (!kForward) {
                tn = tn - std::fabs(tn) * kBoxSlack;
                tf = tf + std::fabs(tf) * kBoxSlack;
            }
            dist[c] = tn;
            if (tn <= tf) bits |= 1u << c;
        }
        return bits;
    }

    // The leaf's triangles first .. first + count - 1 of the rows: the scalar reference's ray_rows.
    static void leaf(const WatertightRay& w, const float* rows, std::size_t stride, std::uint32_t first, int count,
                     LaneHits& out) {
        triangle_kernels(Isa::scalar).ray_rows(w, rows, stride, first, count, out);
    }

    // Two leaves in one test (count + count_b <= 16): lanes 0 .. count - 1 the first leaf's block,
    // then the second's, each lane as leaf() gives it.
    static void leaves(const WatertightRay& w, const float* rows, int count, const float* rows_b, int count_b,
                       LaneHits& out) {
        join_leaves(w, rows, count, rows_b, count_b, out, leaf);
    }
};

// One ray's walk from the root, front to back; kForward: the ray's tnear >= 0 (the scaled-reciprocal
// form of the box tests).
template <class Lanes, bool kOcclusion, bool kCount, bool kForward>
Hit walk_wide(const WideBvh& bvh, const Ray& ray, QueryCounters* counters) {
    struct Entry {
        std::uint32_t ref;
        float tnear;
    };
    Entry stack[WideBvh::kMaxDepth * (kWidth - 1) + 1];
    int top = 0;
    const typename Lanes::Prepared prepared = Lanes::prepare(make_box_ray(ray));
    WatertightRay wray = make_watertight_ray(ray);
    float tfar = ray.tfar;
    Hit best;
    std::uint32_t ref = bvh.root;
    for (;;) {
        if (!is_leaf(ref)) {
            if constexpr (kCount) ++counters->inner_steps;
            const WideNode& node = bvh.nodes[node_index(ref)];
            alignas(64) float dist[kWidth];
            std::uint32_t bits =
                Lanes::template node<kForward>(prepared, node, node_children(ref), ray.tnear, tfar, dist);
            if (bits != 0) {
                int c = __builtin_ctz(bits);
                bits &= bits - 1;
                if (bits == 0) {
                    ref = node.child[c];
                    continue;
                }
                // Several: for occlusion pushed in the node's order (any hit ends the walk, and the
                // insertion cost more than the order saved: docs/wide_bvh.md); else nearest on top
                // (insertion by entry distance; at equal distance the later child first, the same
                // order for every policy). Tried and not kept: their memory requested here; sorting
                // every hit child's key by an AVX-512 network; four rays' walks interleaved a step
                // each (docs/streams.md).
                const int base = top;
                stack[top++] = Entry{node.child[c], dist[c]};
                do {
                    c = __builtin_ctz(bits);
                    bits &= bits - 1;
                    const Entry e{node.child[c], dist[c]};
                    int k = top++;
                    if constexpr (!kOcclusion)
                        for (; k > base && stack[k - 1].tnear < e.tnear; --k) stack[k] = stack[k - 1];
                    stack[k] = e;
                } while (bits != 0);
                ref = stack[--top].ref;
                continue;
            }
        } else {
            const std::uint32_t first = leaf_first(ref);
            const int count = int(leaf_count(ref));
            // A leaf next on the stack joins this one's test when both fit one test of 16 lanes (and,
            // for the closest hit, its entry is not beyond the hit so far): the walk would test it
            // next, and one test's chain of dependent operations is spared. Its hits are no nearer
            // than its entry, so the answer is the one the two tests in turn give. (Up to four leaves
            // in one test measured slower: docs/wide_bvh.md.)
            std::uint32_t first_b = 0;
            int count_b = 0;
            if (top != 0 && is_leaf(stack[top - 1].ref) &&
                count + int(leaf_count(stack[top - 1].ref)) <= kMaxLeafTriangles &&
                (kOcclusion || stack[top - 1].tnear <= tfar)) {
                --top;
                first_b = leaf_first(stack[top].ref);
                count_b = int(leaf_count(stack[top].ref));
            }
            if constexpr (kCount) {
                counters->leaves += count_b != 0 ? 2 : 1;
                counters->triangle_tests += std::uint64_t(count + count_b);
            }
            LaneHits lanes;
            const float* rows = bvh.rows.data() + 9 * std::size_t(first);
            if (count_b == 0)
                Lanes::leaf(wray, rows, std::size_t(count), 0, count, lanes);
            else
                Lanes::leaves(wray, rows, count, bvh.rows.data() + 9 * std::size_t(first_b), count_b, lanes);
            const auto id = [&](int i) {
                return bvh.triangle_ids[i < count ? first + std::uint32_t(i) : first_b + std::uint32_t(i - count)];
            };
            if constexpr (kOcclusion) {
                if (lanes.mask != 0) {
                    const int i = __builtin_ctz(lanes.mask);
                    return Hit{lanes.t[i], id(i), lanes.u[i], lanes.v[i]};
                }
            } else {
                for (std::uint32_t m = lanes.mask; m != 0; m &= m - 1) {
                    const int i = __builtin_ctz(m);
                    if (lanes.t[i] < best.t) best = Hit{lanes.t[i], id(i), lanes.u[i], lanes.v[i]};
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

template <class Lanes, bool kOcclusion, bool kCount>
Hit traverse_wide(const WideBvh& bvh, const Ray& ray, QueryCounters* counters) {
    if constexpr (kCount) ++counters->rays;
    if (!describes_segment(ray) || bvh.root == kEmpty) return Hit{};
    if (ray.tnear >= 0.0f) return walk_wide<Lanes, kOcclusion, kCount, true>(bvh, ray, counters);
    return walk_wide<Lanes, kOcclusion, kCount, false>(bvh, ray, counters);
}

// The kernel table of a lane policy (the scalar reference's in wide_bvh_traversal.cpp, the SIMD
// ones in the per-ISA units).
template <class Lanes>
struct WideBvhTable {
    template <bool kOcclusion>
    static Hit plain(const WideBvh& bvh, const Ray& ray) {
        return traverse_wide<Lanes, kOcclusion, false>(bvh, ray, nullptr);
    }
    template <bool kOcclusion>
    static Hit counted(const WideBvh& bvh, const Ray& ray, QueryCounters* c) {
        return traverse_wide<Lanes, kOcclusion, true>(bvh, ray, c);
    }
    static constexpr WideBvhKernels make(Isa isa) {
        return WideBvhKernels{isa,           plain<false>,       plain<true>,          counted<false>,
                              counted<true>, Lanes::packet_node, Lanes::packet_bounds, Lanes::packet_leaf};
    }
};

}  // namespace beamtrace::bvh
