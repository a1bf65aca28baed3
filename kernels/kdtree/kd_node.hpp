#pragma once
// The compact kd-tree node (8 bytes) and the tree's storage.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "beamtrace/kdtree.hpp"
#include "common/triangle_kernels.hpp"

namespace beamtrace {

namespace kdtree {
struct PacketTables;
}

// Inner node: split position, axis (0..2) in the low two bits, index of the upper child in the other
// 30 (the lower child is the next node: nodes are stored depth first).
// Leaf: triangle count, 3 in the low two bits, offset of its triangle ids in the other 30.
struct KdNode {
    union {
        float split;
        std::uint32_t count;
    };
    std::uint32_t bits;

    static constexpr std::uint32_t kLeafTag = 3;
    static constexpr std::uint32_t kMaxIndex = (1u << 30) - 1;

    bool is_leaf() const { return (bits & 3u) == kLeafTag; }
    int axis() const { return int(bits & 3u); }
    std::uint32_t upper_child() const { return bits >> 2; }
    std::uint32_t offset() const { return bits >> 2; }
    std::uint32_t triangle_count() const { return count; }

    static KdNode inner(int axis, float split, std::uint32_t upper) {
        KdNode n;
        n.split = split;
        n.bits = (upper << 2) | std::uint32_t(axis);
        return n;
    }
    static KdNode leaf(std::uint32_t offset, std::uint32_t count) {
        KdNode n;
        n.count = count;
        n.bits = (offset << 2) | kLeafTag;
        return n;
    }
};
static_assert(sizeof(KdNode) == 8, "kd-tree nodes are 8 bytes");

struct KdTree::Impl {
    Scene scene;
    Box bounds;                               // box of the root cell
    std::vector<KdNode> nodes;                // nodes[0] is the root
    std::vector<std::uint32_t> triangle_ids;  // leaves' ranges
    // The corners of triangle_ids[r] at r: each leaf's triangles side by side in memory, read front
    // to back by traversals (instead of scattered over the scene; room: a third less time per
    // packet). 36 bytes per reference.
    std::vector<Triangle> leaf_triangles;
    KdBuildStats stats;
    const TriangleKernels* kernels = nullptr;

    explicit Impl(const Scene& s) : scene(s) {}

    // The tables of packet traversal (kdtree/packet/packet_tables.hpp), made on first use (thread-safe).
    const kdtree::PacketTables& packet_tables() const;
    // Bytes of the packet tables, 0 until they are made.
    std::size_t packet_table_bytes() const;

    // Fills leaf_triangles from triangle_ids (once the leaves are final).
    void gather_leaf_triangles() {
        leaf_triangles.resize(triangle_ids.size());
        for (std::size_t r = 0; r < triangle_ids.size(); ++r) leaf_triangles[r] = scene.triangle(triangle_ids[r]);
    }

private:
    mutable std::once_flag packet_once_;
    mutable std::shared_ptr<const kdtree::PacketTables> packet_;             // owner, set once under packet_once_
    mutable std::atomic<const kdtree::PacketTables*> packet_made_{nullptr};  // readable by anyone
};

}  // namespace beamtrace
