#pragma once
// Mlrta's private state: the tree, its settings, and per-node tables computed once.
#include <vector>

#include "beamtrace/mlrta.hpp"
#include "kdtree/kd_node.hpp"
#include "mlrta/lane_slabs.hpp"
#include "mlrta/packet_frustum.hpp"

namespace beamtrace {

struct Mlrta::Impl {
    KdTree tree;
    MlrtaSettings settings;
    std::vector<std::uint32_t> subtree_nodes;  // per node: nodes in its subtree (itself included)
    std::vector<std::uint8_t> covered_leaf;    // per node: a flat leaf completely covered by its triangles
    std::vector<Box> geometry_boxes;           // per leaf: its triangles clipped to its cell (XP keeps no boxes)
    mlrta::FrustumCullKernel frustum_cull;     // same instruction set as the tree's triangle kernels
    mlrta::LaneBoxKernel lane_box;             // likewise

    Impl(const KdTree& t, const MlrtaSettings& s)
        : tree(t),
          settings(s),
          frustum_cull(mlrta::frustum_cull_kernel(t.impl().kernels->isa)),
          lane_box(mlrta::lane_box_kernel(t.impl().kernels->isa)) {}
    const KdTree::Impl& kd() const { return tree.impl(); }
};

}  // namespace beamtrace
