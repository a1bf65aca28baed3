#pragma once
// The ray-space hierarchy of one call (CRSH steps 3-5): the rays that describe a segment, keyed and
// radix-sorted (or in input order for RAH), level-1 nodes of `fanout` consecutive rays, each upper
// level merging `fanout` consecutive nodes of the level below.
#include <cstdint>
#include <span>
#include <vector>

#include "beamtrace/crsh.hpp"
#include "beamtrace/query.hpp"
#include "crsh/ray_keys.hpp"
#include "crsh/ray_node.hpp"

namespace beamtrace::crsh {

struct RayHierarchy {
    std::vector<std::uint32_t> order;          // indices of the call's rays, in hierarchy order
    std::vector<std::vector<RayNode>> levels;  // levels[0]: level 1 (first/count: positions in order)
    std::size_t top_count() const { return levels.empty() ? 0 : levels.back().size(); }
};

// Runs its parallel parts (bounding rays and keys, level-1 nodes) with TBB in the caller's arena when
// `parallel`. With counters: crsh.rays, crsh.nodes[], and the key, sort and hierarchy times.
RayHierarchy build_ray_hierarchy(std::span<const Ray> rays, const CrshSettings& settings, const Box& scene_box,
                                 bool parallel, QueryCounters* counters);

// A level-1 node over bounding rays (not empty): the sphere about the box centre of the starts,
// reaching the farthest; Szecsi's cone of the directions, its spread then the largest angle from its
// axis (never wider than Szecsi's, docs/crsh.md); the longest of their lengths.
RayNode leaf_node(std::span<const BoundingRay> rays);
// A node over nodes (not empty): the notes' merge of spheres (mean centre, farthest reach) and cones.
RayNode merged_node(std::span<const RayNode> children);

}  // namespace beamtrace::crsh
