#include "mlrta/covered_leaves.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "kdtree/split_events.hpp"

namespace beamtrace::mlrta {

namespace {

std::uint32_t count_subtree(const std::vector<KdNode>& nodes, std::uint32_t i, std::vector<std::uint32_t>& out) {
    // Iterative post-order would need more code; the recursion depth is the tree depth (<= 60).
    std::uint32_t n = 1;
    if (!nodes[i].is_leaf()) {
        n += count_subtree(nodes, i + 1, out);
        n += count_subtree(nodes, nodes[i].upper_child(), out);
    }
    out[i] = n;
    return n;
}

struct P2 {
    double u, v;
};

// Projections of two triangles on an axis overlap in more than a point?
bool overlap_on(const std::array<P2, 3>& a, const std::array<P2, 3>& b, double nu, double nv) {
    double amin = INFINITY, amax = -INFINITY, bmin = INFINITY, bmax = -INFINITY;
    for (int i = 0; i < 3; ++i) {
        const double pa = a[i].u * nu + a[i].v * nv, pb = b[i].u * nu + b[i].v * nv;
        amin = std::min(amin, pa);
        amax = std::max(amax, pa);
        bmin = std::min(bmin, pb);
        bmax = std::max(bmax, pb);
    }
    return amax > bmin && bmax > amin;
}

bool interiors_overlap(const std::array<P2, 3>& a, const std::array<P2, 3>& b) {
    for (const std::array<P2, 3>* t : {&a, &b})
        for (int i = 0; i < 3; ++i) {
            const P2& p = (*t)[i];
            const P2& q = (*t)[(i + 1) % 3];
            if (!overlap_on(a, b, -(q.v - p.v), q.u - p.u)) return false;
        }
    return true;
}

bool leaf_is_covered(const KdTree::Impl& tree, const KdNode& leaf, const Box& box) {
    int k = -1;
    for (int a = 0; a < 3; ++a)
        if (box.lower[a] == box.upper[a]) k = a;
    const std::uint32_t count = leaf.triangle_count();
    if (k < 0 || count == 0 || count > 64) return false;
    const int u = (k + 1) % 3, v = (k + 2) % 3;
    const double face = double(box.upper[u] - box.lower[u]) * double(box.upper[v] - box.lower[v]);
    if (!(face > 0.0)) return false;
    std::vector<std::array<P2, 3>> flat;
    double area = 0.0;
    for (std::uint32_t j = 0; j < count; ++j) {
        const Triangle& t = tree.scene.triangle(tree.triangle_ids[leaf.offset() + j]);
        if (t.v0[k] != box.lower[k] || t.v1[k] != box.lower[k] || t.v2[k] != box.lower[k]) continue;
        const double a = kd::clipped_planar_area(t, box, k);
        if (!(a > 0.0)) continue;
        area += a;
        flat.push_back({P2{t.v0[u], t.v0[v]}, P2{t.v1[u], t.v1[v]}, P2{t.v2[u], t.v2[v]}});
    }
    if (area < face * (1.0 - 1e-9)) return false;
    for (std::size_t i = 0; i < flat.size(); ++i)
        for (std::size_t j = i + 1; j < flat.size(); ++j) {
            if (interiors_overlap(flat[i], flat[j])) return false;
        }
    return true;
}

void mark_covered(const KdTree::Impl& tree, std::uint32_t i, const Box& box, std::vector<std::uint8_t>& out) {
    const KdNode& n = tree.nodes[i];
    if (n.is_leaf()) {
        out[i] = leaf_is_covered(tree, n, box) ? 1 : 0;
        return;
    }
    Box lower = box, upper = box;
    lower.upper[n.axis()] = n.split;
    upper.lower[n.axis()] = n.split;
    mark_covered(tree, i + 1, lower, out);
    mark_covered(tree, n.upper_child(), upper, out);
}

}  // namespace

std::vector<std::uint32_t> subtree_sizes(const KdTree::Impl& tree) {
    std::vector<std::uint32_t> out(tree.nodes.size(), 1);
    if (!tree.nodes.empty()) count_subtree(tree.nodes, 0, out);
    return out;
}

std::vector<std::uint8_t> covered_flat_leaves(const KdTree::Impl& tree) {
    std::vector<std::uint8_t> out(tree.nodes.size(), 0);
    if (!tree.nodes.empty()) mark_covered(tree, 0, tree.bounds, out);
    return out;
}

}  // namespace beamtrace::mlrta
