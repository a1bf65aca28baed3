#pragma once
// Mlrta's private state: the tree, its settings, the per-node tables of the entry-point search, and
// the context of the tree's packet traversal its tiles finish with, the wide BVH of its occlusion packets.
#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

#include "beamtrace/mlrta.hpp"
#include "bvh/wide_bvh.hpp"
#include "common/access.hpp"
#include "kdtree/kd_node.hpp"
#include "kdtree/packet/packet_traversal.hpp"

namespace beamtrace {

struct Mlrta::Impl {
    KdTree tree;
    MlrtaSettings settings;
    std::vector<std::uint32_t> subtree_nodes;  // per node: nodes in its subtree (itself included)
    std::vector<std::uint8_t> covered_leaf;    // per node: a flat leaf completely covered by its triangles
    kdtree::PacketTraversalContext packets;    // the tree's packet traversal, MLRTA's culling switch
    // The wide BVH of occlusion packets (MlrtaExperimental::shadow_bvh), built once, on demand.
    mutable std::once_flag bvh_once;
    mutable std::shared_ptr<const bvh::WideBvh> bvh;
    mutable std::atomic<const bvh::WideBvh*> bvh_made{nullptr};  // set once bvh is (memory_bytes)
    const bvh::WideBvh& wide_bvh() const;

    Impl(const KdTree& t, const MlrtaSettings& s);
    const KdTree::Impl& kd() const { return detail::Access::impl(tree); }
    const kdtree::PacketKernels& kernels() const { return *packets.tables.kernels; }
};

}  // namespace beamtrace
