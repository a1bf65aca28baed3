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

// The slab distances of a child: t = (plane - origin) * reciprocal per plane, entry = the largest of
// the near planes' and the ray's tnear, exit = the smallest of the far planes' and tfar, each as a
// two-level tree max(max(x, y), max(z, tnear)) (a short chain of dependent operations). A distance is
// NaN when the origin lies in a plane the ray runs along (0 * inf): max(a, b) and min(a, b) are
// a > b ? a : b and a < b ? a : b, what the SIMD max and min instructions do (a NaN first operand
// gives the second, a NaN second operand is kept and then dropped by the outer level, whose second
// operand is never NaN), so a NaN distance only ever drops a constraint: no box is culled by it.
// The slack: for a ray with tnear >= 0 (kForward) entry * (1 - s) <= exit * (1 + s) (entry >= 0, so
// these bound the true distances; an exit below 0 fails either way, as it must); otherwise
// entry - |entry| s <= exit + |exit| s.
constexpr float kEntryScale = 1.0f - kBoxSlack, kExitScale = 1.0f + kBoxSlack;

inline float max_keeping(float a, float b) { return a > b ? a : b; }
inline float min_keeping(float a, float b) { return a < b ? a : b; }

// The reference policy.
struct ScalarLanes {
    using Prepared = BoxRay;
    static BoxRay prepare(const BoxRay& r) { return r; }

    // Bit c set when child c's box meets [tnear, tfar]; dist[c] its (slackened) entry distance.
    template <bool kForward>
    static std::uint32_t node(const BoxRay& r, const WideNode& n, float tnear, float tfar, float* dist) {
        std::uint32_t bits = 0;
        for (int c = 0; c < kWidth; ++c) {
            float t0[3], t1[3];
            for (int a = 0; a < 3; ++a) {
                const float near_plane = r.upper_first[a] ? n.upper[a][c] : n.lower[a][c];
                const float far_plane = r.upper_first[a] ? n.lower[a][c] : n.upper[a][c];
                t0[a] = (near_plane - r.org[a]) * r.inv[a];
                t1[a] = (far_plane - r.org[a]) * r.inv[a];
            }
            float tn = max_keeping(max_keeping(t0[0], t0[1]), max_keeping(t0[2], tnear));
            float tf = min_keeping(min_keeping(t1[0], t1[1]), min_keeping(t1[2], tfar));
            if constexpr (kForward) {
                tn = tn * kEntryScale;
                tf = tf * kExitScale;
            } else {
                tn = tn - std::fabs(tn) * kBoxSlack;
                tf = tf + std::fabs(tf) * kBoxSlack;
            }
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

// One ray's walk, a node or a leaf a step, so that several walks can be interleaved (their chains
// of dependent loads and arithmetic overlap: traverse_wide_many).
template <class Lanes, bool kOcclusion, bool kCount>
class WideWalk {
public:
    // Starts the walk of `ray`; false when there is none (no segment, or an empty BVH): no hit.
    bool start(const WideBvh& bvh, const Ray& ray, QueryCounters* counters) {
        if constexpr (kCount) ++counters->rays;
        if (!describes_segment(ray) || bvh.root == kEmpty) return false;
        prepared_ = Lanes::prepare(make_box_ray(ray));
        wray_ = make_watertight_ray(ray);
        tnear_ = ray.tnear;
        tfar_ = ray.tfar;
        forward_ = ray.tnear >= 0.0f;
        best_ = Hit{};
        ref_ = bvh.root;
        top_ = 0;
        return true;
    }

    // One node or leaf; false when the walk is over (answer() is final).
    bool step(const WideBvh& bvh, QueryCounters* counters) {
        if (!is_leaf(ref_)) {
            if constexpr (kCount) ++counters->inner_steps;
            const WideNode& node = bvh.nodes[ref_];
            alignas(64) float dist[16];
            std::uint32_t bits = forward_ ? Lanes::template node<true>(prepared_, node, tnear_, tfar_, dist)
                                          : Lanes::template node<false>(prepared_, node, tnear_, tfar_, dist);
            if (bits != 0) {
                int c = __builtin_ctz(bits);
                bits &= bits - 1;
                if (bits == 0) {
                    ref_ = node.child[c];
                    return true;
                }
                // Several: pushed nearest on top (insertion by entry distance; at equal distance the
                // later child first, the same order for every policy).
                const int base = top_;
                stack_[top_++] = Entry{node.child[c], dist[c]};
                do {
                    c = __builtin_ctz(bits);
                    bits &= bits - 1;
                    const Entry e{node.child[c], dist[c]};
                    int k = top_++;
                    while (k > base && stack_[k - 1].tnear < e.tnear) {
                        stack_[k] = stack_[k - 1];
                        --k;
                    }
                    stack_[k] = e;
                } while (bits != 0);
                ref_ = stack_[--top_].ref;
                return true;
            }
        } else {
            const std::uint32_t first = leaf_first(ref_);
            const int count = int(leaf_count(ref_));
            if constexpr (kCount) {
                ++counters->leaves;
                counters->triangle_tests += std::uint64_t(count);
            }
            LaneHits lanes;
            Lanes::leaf(wray_, bvh.rows.data() + 9 * std::size_t(first), std::size_t(count), 0, count, lanes);
            if constexpr (kOcclusion) {
                if (lanes.mask != 0) {
                    const int i = __builtin_ctz(lanes.mask);
                    best_ = Hit{lanes.t[i], bvh.triangle_ids[first + std::uint32_t(i)], lanes.u[i], lanes.v[i]};
                    return false;
                }
            } else {
                for (std::uint32_t m = lanes.mask; m != 0; m &= m - 1) {
                    const int i = __builtin_ctz(m);
                    if (lanes.t[i] < best_.t)
                        best_ = Hit{lanes.t[i], bvh.triangle_ids[first + std::uint32_t(i)], lanes.u[i], lanes.v[i]};
                }
                if (best_.hit()) tfar_ = wray_.tfar = best_.t;
            }
        }
        // The next entry, skipping those that start beyond the closest hit.
        for (;;) {
            if (top_ == 0) return false;
            const Entry& e = stack_[--top_];
            if (!kOcclusion && e.tnear > tfar_) continue;
            ref_ = e.ref;
            return true;
        }
    }

    const Hit& answer() const { return best_; }

private:
    struct Entry {
        std::uint32_t ref;
        float tnear;
    };
    typename Lanes::Prepared prepared_;
    WatertightRay wray_;
    float tnear_ = 0, tfar_ = 0;
    bool forward_ = true;
    Hit best_;
    std::uint32_t ref_ = kEmpty;
    int top_ = 0;
    Entry stack_[WideBvh::kMaxDepth * (kWidth - 1) + 1];
};

template <class Lanes, bool kOcclusion, bool kCount>
Hit traverse_wide(const WideBvh& bvh, const Ray& ray, QueryCounters* counters) {
    WideWalk<Lanes, kOcclusion, kCount> walk;
    if (!walk.start(bvh, ray, counters)) return Hit{};
    while (walk.step(bvh, counters)) {
    }
    return walk.answer();
}

// How many walks traverse_wide_many interleaves.
constexpr int kInterleavedWalks = 4;

// Rays 0 .. n - 1 answered into hits[0 .. n - 1], kInterleavedWalks walks interleaved a step each in
// turn (a finished walk takes the next ray): each ray's answer is traverse_wide's.
template <class Lanes, bool kOcclusion, bool kCount>
void traverse_wide_many(const WideBvh& bvh, const Ray* rays, std::uint32_t n, Hit* hits, QueryCounters* counters) {
    constexpr int kWalks = kInterleavedWalks;
    WideWalk<Lanes, kOcclusion, kCount> walks[kWalks];
    std::uint32_t ray_of[kWalks] = {};
    std::uint32_t next = 0;
    // The next ray with a walk into slot k; false when none is left.
    const auto fill = [&](int k) {
        while (next < n) {
            const std::uint32_t i = next++;
            if (walks[k].start(bvh, rays[i], counters)) {
                ray_of[k] = i;
                return true;
            }
            hits[i] = Hit{};
        }
        return false;
    };
    std::uint32_t live = 0;  // bit k: slot k walks
    for (int k = 0; k < kWalks; ++k)
        if (fill(k)) live |= 1u << k;
    while (live != 0) {
        for (int k = 0; k < kWalks; ++k) {
            if (((live >> k) & 1u) == 0 || walks[k].step(bvh, counters)) continue;
            hits[ray_of[k]] = walks[k].answer();
            if (!fill(k)) live &= ~(1u << k);
        }
    }
}

}  // namespace beamtrace::bvh

namespace beamtrace::bvh {

// traverse_wide_many with the counting chosen at run time (counters null: none), for the tables.
template <class Lanes>
void trace_wide_many(const WideBvh& bvh, const Ray* rays, std::uint32_t n, bool occlusion, Hit* hits,
                     QueryCounters* counters) {
    if (counters) {
        if (occlusion)
            traverse_wide_many<Lanes, true, true>(bvh, rays, n, hits, counters);
        else
            traverse_wide_many<Lanes, false, true>(bvh, rays, n, hits, counters);
    } else {
        if (occlusion)
            traverse_wide_many<Lanes, true, false>(bvh, rays, n, hits, nullptr);
        else
            traverse_wide_many<Lanes, false, false>(bvh, rays, n, hits, nullptr);
    }
}

}  // namespace beamtrace::bvh
