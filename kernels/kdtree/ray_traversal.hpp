#pragma once
// Single-ray kd-tree traversal (kd_traversal.cpp), for the tree's own queries and for the packet
// traversal's lanes that go alone.
#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "kdtree/kd_node.hpp"

namespace beamtrace::kdtree {

// Closest hit (or, with kOcclusion, any hit: Hit::hit() tells) of the ray in the tree; with kCount,
// counters->rays, inner_steps, leaves and triangle_tests grow.
template <bool kOcclusion, bool kCount>
Hit traverse_ray(const KdTree::Impl& tree, const Ray& ray, QueryCounters* counters);

inline Hit intersect_one(const KdTree::Impl& tree, const Ray& ray) {
    return traverse_ray<false, false>(tree, ray, nullptr);
}
inline bool occluded_one(const KdTree::Impl& tree, const Ray& ray) {
    return traverse_ray<true, false>(tree, ray, nullptr).hit();
}

}  // namespace beamtrace::kdtree
