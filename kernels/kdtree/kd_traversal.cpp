// Single-ray kd-tree traversal: front to back with a stack of (node, t_min, t_max), early exit as
// soon as the closest hit lies inside the current cell. Counting is a template parameter, so the
// measured path and the counted path are the same code.
#include <cmath>

#include "common/ray_batches.hpp"
#include "common/ray_validity.hpp"
#include "common/triangle_reference.hpp"
#include "kdtree/ray_traversal.hpp"

namespace beamtrace::kdtree {
namespace {

constexpr int kStackSize = 64;

struct StackEntry {
    std::uint32_t node;
    float tmin, tmax;
};

// The walk of the subtree at `start` for [tmin, tmax], front to back from `best` (the closest hit so
// far; wray.tfar its distance or the ray's tfar): the traversal from the root and the group
// traversal's lanes that go on alone (traverse_subtree) share it.
// Leaves are tested from corner rows (rows, stride: kdtree::PacketTables) with kRows.
template <bool kOcclusion, bool kCount, bool kSmallestId, bool kRows>
inline Hit walk(const KdTree::Impl& tree, const Ray& ray, const Float3& inv, WatertightRay wray,
                std::uint32_t start, float tmin, float tmax, Hit best, const float* rows,
                std::size_t stride, QueryCounters* counters) {
    const KdNode* nodes = tree.nodes.data();
    const std::uint32_t* ids = tree.triangle_ids.data();
    const Triangle* tris = tree.leaf_triangles.data();
    const TriangleKernels& kernels = *tree.kernels;

    StackEntry stack[kStackSize];
    int top = 0;
    bool in_plane = false;  // some stacked cell repeats the current interval (see below)
    std::uint32_t index = start;
    for (;;) {
        const KdNode& node = nodes[index];
        if (!node.is_leaf()) {
            if constexpr (kCount) ++counters->inner_steps;
            const int axis = node.axis();
            const float o = ray.org[axis], d = ray.dir[axis];
            const float tplane = (node.split - o) * inv[axis];
            // A ray starting exactly in the plane visits the cell behind it first, with the interval
            // [tmin, 0], so that hits at t = 0 on triangles kept on that side are found.
            const bool lower_first = o < node.split || (o == node.split && d > 0.0f);
            std::uint32_t first = lower_first ? index + 1 : node.upper_child();
            std::uint32_t second = lower_first ? node.upper_child() : index + 1;
            // The plane crossed behind the origin (reached only with a negative tnear): before the
            // crossing the ray is on the far side of the origin's cell, after it in the origin's.
            if (tplane < 0.0f) std::swap(first, second);
            if (tplane != tplane) {  // the ray lies in the split plane: both children, same interval
                stack[top++] = StackEntry{second, tmin, tmax};
                index = first;
                in_plane = true;
                continue;
            }
            // The plane beyond the interval: the first child alone; before it: the second alone;
            // else both, the second stacked. Without branches (the outcome is unpredictable): the
            // entry is written every time and kept when both children are visited (top <= the
            // tree's depth, at most 60, below kStackSize either way).
            const bool beyond = tplane > tmax + slack(tmax);
            const bool before = !beyond && tplane < tmin - slack(tmin);
            const bool both = !beyond && !before;
            stack[top] = StackEntry{second, tplane, tmax};
            top += both ? 1 : 0;
            index = before ? second : first;
            tmax = both ? tplane : tmax;
            continue;
        }
        // Leaf: test its triangles, 8 (or 4) at a time.
        const std::uint32_t count = node.triangle_count();
        const std::uint32_t* leaf = ids + node.offset();
        const Triangle* corners = tris + node.offset();
        if constexpr (kCount) {
            ++counters->leaves;
            counters->triangle_tests += count;
        }
        bool occluded = false;
        const auto on_batch = [&](std::uint32_t j, int, const LaneHits& lanes) {
            if constexpr (kOcclusion) {
                if (lanes.mask) {
                    best.triangle = leaf[j];
                    occluded = true;
                    return false;
                }
            } else {
                for (std::uint32_t m = lanes.mask; m; m &= m - 1) {
                    const int i = __builtin_ctz(m);
                    const bool nearer =
                        lanes.t[i] < best.t ||
                        (kSmallestId && lanes.t[i] == best.t && leaf[j + std::uint32_t(i)] < best.triangle);
                    if (nearer) {
                        best = Hit{lanes.t[i], leaf[j + std::uint32_t(i)], lanes.u[i], lanes.v[i]};
                        wray.tfar = lanes.t[i];
                    }
                }
            }
            return true;
        };
        if constexpr (kRows)  // 16 at a time from the corner rows (the same answers)
            test_ray_in_rows(kernels, wray, rows, stride, node.offset(), count, on_batch);
        else
            test_ray_in_batches(kernels, wray, count, [&](std::uint32_t j) { return corners + j; }, on_batch);
        if (kOcclusion && occluded) return best;
        if (!kOcclusion && !in_plane && best.t < tmax - slack(tmax)) return best;  // nothing nearer is left
        // Next cell from the stack, skipping cells that start beyond the closest hit. (The stack is
        // not sorted by tmin: a ray lying in a split plane pushes a cell with the current interval.)
        for (;;) {
            if (top == 0) return best;
            const StackEntry& e = stack[--top];
            if (!kOcclusion && e.tmin > best.t + slack(best.t)) continue;
            index = e.node;
            tmin = e.tmin;
            tmax = e.tmax;
            break;
        }
    }
}

// A ray from the root: validity, the cut to the tree's box, the walk.
template <bool kOcclusion, bool kCount, bool kSmallestId, bool kRows>
Hit from_root(const KdTree::Impl& tree, const Ray& ray, const float* rows, std::size_t stride, QueryCounters* counters) {
    if constexpr (kCount) ++counters->rays;
    if (!describes_segment(ray)) return Hit{};
    const Float3 inv{1.0f / ray.dir.x, 1.0f / ray.dir.y, 1.0f / ray.dir.z};
    float tmin, tmax;
    if (!clip_to_box(ray, inv, tree.bounds, tmin, tmax)) return Hit{};
    return walk<kOcclusion, kCount, kSmallestId, kRows>(tree, ray, inv, make_watertight_ray(ray), 0, tmin, tmax, Hit{},
                                                        rows, stride, counters);
}

}  // namespace

template <bool kOcclusion, bool kCount, bool kSmallestId>
Hit traverse_ray(const KdTree::Impl& tree, const Ray& ray, QueryCounters* counters) {
    return from_root<kOcclusion, kCount, kSmallestId, false>(tree, ray, nullptr, 0, counters);
}

template <bool kOcclusion, bool kCount>
Hit traverse_ray_in_rows(const KdTree::Impl& tree, const Ray& ray, const float* rows, std::size_t stride,
                         QueryCounters* counters) {
    return from_root<kOcclusion, kCount, false, true>(tree, ray, rows, stride, counters);
}

template <bool kOcclusion, bool kCount>
Hit traverse_subtree(const KdTree::Impl& tree, const Ray& ray, const Float3& inv, const WatertightRay& wray,
                     std::uint32_t node, float tmin, float tmax, const Hit& best, const float* rows, std::size_t stride,
                     QueryCounters* counters) {
    return walk<kOcclusion, kCount, false, true>(tree, ray, inv, wray, node, tmin, tmax, best, rows, stride, counters);
}

#define BEAMTRACE_SINGLE_RAY_WALKS(kOcclusion, kCount)                                                               \
    template Hit traverse_ray<kOcclusion, kCount>(const KdTree::Impl&, const Ray&, QueryCounters*);                     \
    template Hit traverse_ray_in_rows<kOcclusion, kCount>(const KdTree::Impl&, const Ray&, const float*, std::size_t,  \
                                                          QueryCounters*);                                             \
    template Hit traverse_subtree<kOcclusion, kCount>(const KdTree::Impl&, const Ray&, const Float3&,                  \
                                                      const WatertightRay&, std::uint32_t, float, float, const Hit&,   \
                                                      const float*, std::size_t, QueryCounters*);
BEAMTRACE_SINGLE_RAY_WALKS(false, false)
BEAMTRACE_SINGLE_RAY_WALKS(false, true)
BEAMTRACE_SINGLE_RAY_WALKS(true, false)
BEAMTRACE_SINGLE_RAY_WALKS(true, true)
#undef BEAMTRACE_SINGLE_RAY_WALKS
template Hit traverse_ray<false, false, true>(const KdTree::Impl&, const Ray&, QueryCounters*);
template Hit traverse_ray<false, true, true>(const KdTree::Impl&, const Ray&, QueryCounters*);

}  // namespace beamtrace::kdtree
