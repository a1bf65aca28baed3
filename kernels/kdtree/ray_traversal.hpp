#pragma once
// Single-ray kd-tree traversal (kd_traversal.cpp), for the tree's own queries and for the packet
// traversal's lanes that go alone.
#include <cmath>
#include <cstddef>
#include <utility>

#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "common/watertight_ray.hpp"
#include "kdtree/kd_node.hpp"

namespace beamtrace::kdtree {

// Plane and box distances carry rounding, as do the triangle test's t: a hit one ulp inside a cell
// can be computed one ulp outside it. Cell decisions therefore keep a relative slack (about a
// million times finer than any cell, so it costs nothing measurable): a child is skipped, or the
// search ended, only when the distances differ by more than it.
inline float slack(float t) { return std::fabs(t) * (1.0f / 1048576.0f); }

// Clips [ray.tnear, ray.tfar] to the box (inv: the direction's reciprocals); false if the ray misses
// it.
inline bool clip_to_box(const Ray& ray, const Float3& inv, const Box& box, float& tmin, float& tmax) {
    tmin = ray.tnear;
    tmax = ray.tfar;
    for (int k = 0; k < 3; ++k) {
        if (ray.dir[k] == 0.0f) {
            if (ray.org[k] < box.lower[k] || ray.org[k] > box.upper[k]) return false;
            continue;
        }
        float t0 = (box.lower[k] - ray.org[k]) * inv[k];
        float t1 = (box.upper[k] - ray.org[k]) * inv[k];
        if (t0 > t1) std::swap(t0, t1);
        t0 -= slack(t0);
        t1 += slack(t1);
        tmin = t0 > tmin ? t0 : tmin;
        tmax = t1 < tmax ? t1 : tmax;
    }
    return tmin <= tmax;
}

// Closest hit (or, with kOcclusion, any hit: Hit::hit() tells) of the ray in the tree; with kCount,
// counters->rays, inner_steps, leaves and triangle_tests grow. Hits at equal t: the first found, or
// with kSmallestId the smaller triangle id (brute force's rule, which ray classification answers by).
template <bool kOcclusion, bool kCount, bool kSmallestId = false>
Hit traverse_ray(const KdTree::Impl& tree, const Ray& ray, QueryCounters* counters);

// traverse_ray with the leaves tested from the nine corner rows `rows` (stride apart;
// kdtree::PacketTables), 16 triangles at a time: the same answers (the stream's single rays).
template <bool kOcclusion, bool kCount>
Hit traverse_ray_in_rows(const KdTree::Impl& tree, const Ray& ray, const float* rows, std::size_t stride,
                         QueryCounters* counters);

// The same traversal of the subtree at `node` for [tmin, tmax] (the interval the traversal from the
// root has there), going on from `best`, the ray's closest hit so far (Hit{} for none; occlusion: Hit{}),
// with inv the direction's reciprocals (1 / dir, as traverse_ray takes them) and wray =
// make_watertight_ray(ray) whose tfar is best.t when there is a hit. For the stream's
// group traversal, whose lanes' decisions are this traversal's: a lane left alone in a subtree walks
// it here, one step a node instead of a step of the whole group. Leaves are tested from the nine
// corner rows `rows` (stride apart; kdtree::PacketTables), 16 triangles at a time.
template <bool kOcclusion, bool kCount>
Hit traverse_subtree(const KdTree::Impl& tree, const Ray& ray, const Float3& inv, const WatertightRay& wray,
                     std::uint32_t node, float tmin, float tmax, const Hit& best, const float* rows, std::size_t stride,
                     QueryCounters* counters);

inline Hit intersect_one(const KdTree::Impl& tree, const Ray& ray) {
    return traverse_ray<false, false>(tree, ray, nullptr);
}
inline bool occluded_one(const KdTree::Impl& tree, const Ray& ray) {
    return traverse_ray<true, false>(tree, ray, nullptr).hit();
}

}  // namespace beamtrace::kdtree
