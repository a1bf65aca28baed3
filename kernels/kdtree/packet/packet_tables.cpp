// Packet traversal's tables: the leaves' geometry boxes, the corner rows, and the tree's packet kernels.
#include "kdtree/packet/packet_tables.hpp"

#include <algorithm>
#include <cmath>

#include "kdtree/kd_node.hpp"
#include "kdtree/split_events.hpp"

namespace beamtrace {

namespace {

void mark_geometry(const KdTree::Impl& tree, std::uint32_t i, const Box& cell, std::vector<Box>& out) {
    const KdNode& n = tree.nodes[i];
    if (!n.is_leaf()) {
        Box lower = cell, upper = cell;
        lower.upper[n.axis()] = n.split;
        upper.lower[n.axis()] = n.split;
        mark_geometry(tree, i + 1, lower, out);
        mark_geometry(tree, n.upper_child(), upper, out);
        return;
    }
    const Float3 e = cell.extent();
    const double slack = 1e-6 * (double(std::max({e.x, e.y, e.z})) + 1e-30);
    for (std::uint32_t j = 0; j < n.triangle_count(); ++j) {
        const Box b = kd::clipped_bounds(tree.leaf_triangles[n.offset() + j], cell, slack);
        if (!b.empty()) out[i].extend(b);
    }
}

// Row c holds coordinate c % 3 of corner c / 3 of every leaf triangle, then 16 zeros.
void fill_corner_rows(const std::vector<Triangle>& tris, kdtree::PacketTables& t) {
    t.corner_stride = tris.size() + 16;
    t.corner_rows.assign(9 * t.corner_stride, 0.0f);
    for (std::size_t r = 0; r < tris.size(); ++r) {
        const float* f = &tris[r].v0.x;
        for (int c = 0; c < 9; ++c) t.corner_rows[std::size_t(c) * t.corner_stride + r] = f[c];
    }
}

}  // namespace

const kdtree::PacketTables& KdTree::Impl::packet_tables() const {
    std::call_once(packet_once_, [this] {
        auto t = std::make_shared<kdtree::PacketTables>();
        t->geometry_boxes.resize(nodes.size());
        if (!nodes.empty()) mark_geometry(*this, 0, bounds, t->geometry_boxes);
        fill_corner_rows(leaf_triangles, *t);
        float scale = bounds.diagonal();
        for (int k = 0; k < 3; ++k) scale = std::max({scale, std::fabs(bounds.lower[k]), std::fabs(bounds.upper[k])});
        t->pad = std::ldexp(scale, -20);
        t->kernels = &simd::select<kdtree::PacketKernels>(kernels->isa);
        packet_ = std::move(t);
        packet_made_.store(packet_.get(), std::memory_order_release);
    });
    return *packet_;
}

std::size_t KdTree::Impl::packet_table_bytes() const {
    const kdtree::PacketTables* t = packet_made_.load(std::memory_order_acquire);
    return t ? t->bytes() : 0;
}

}  // namespace beamtrace
