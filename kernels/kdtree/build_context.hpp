#pragma once
// What the kd-tree's builders share while they build one tree: the scene, the rules, the tree being
// written (nodes depth first, leaves' triangle ids), and the steps every node takes whichever way
// its split was found: stopping (leaf rules, MLRTA rule 3), writing a leaf, writing an inner node
// around its two subtrees, and MLRTA rule 2's test of a plane covered by triangles.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "kdtree/kd_node.hpp"
#include "kdtree/split_events.hpp"
#include "kdtree/split_search.hpp"

namespace beamtrace::kd {

class BuildContext {
public:
    BuildContext(const Scene& scene, const KdBuildRules& rules, const KdTree::Progress& progress, KdTree::Impl& out);

    const Scene& scene() const { return scene_; }
    const KdBuildRules& rules() const { return rules_; }
    // Slack of the conservative clipping (2^-21 of the scene's size; split_events.hpp).
    double slack() const { return slack_; }

    // Remembers a triangle's area (for rule 2) and counts it as one the tree holds.
    void add_triangle(std::uint32_t tri, double area) {
        area_[tri] = area;
        ++triangles_held_;
    }
    // The automatic depth limit counts the triangles added so far: call once they all are.
    void set_max_depth();

    // True if a cell of n triangles at this depth must be a leaf (counts MLRTA rule 3's leaves).
    bool stops_here(const Box& box, std::size_t n, int depth);

    // Writes a leaf of the triangle ids `append(ids)` pushes onto the tree's id list.
    template <class Append>
    void make_leaf(const Box& box, Append&& append) {
        const std::size_t offset = out_.triangle_ids.size();
        append(out_.triangle_ids);
        std::sort(out_.triangle_ids.begin() + std::ptrdiff_t(offset), out_.triangle_ids.end());
        finish_leaf(box, offset);
    }

    // Writes an inner node for `split` of `box` around the lower subtree `build_left()` writes and
    // the upper one `build_right()` writes (in that order: nodes are depth first).
    template <class Left, class Right>
    void make_inner(const SplitChoice& split, const Box& box, Left&& build_left, Right&& build_right) {
        if (split.rule == Rule::empty_cell) ++out_.stats.empty_cell_splits;
        if (split.rule == Rule::flat_cell) ++out_.stats.flat_cell_splits;
        sah_cost_ += rules_.traversal_cost * double(box.surface_area());
        const std::size_t index = out_.nodes.size();
        out_.nodes.push_back(KdNode::leaf(0, 0));
        build_left();
        out_.nodes[index] = KdNode::inner(split.axis, split.pos, std::uint32_t(out_.nodes.size()));
        build_right();
    }

    void count_binned_split() { ++out_.stats.binned_splits; }

    // True if the triangles tri_of(*it) of [begin, end) (all lying in the plane axis = const) cover
    // the cell's face of area `cross_section` (MLRTA rule 2): whole-triangle areas first, exact
    // clipped areas if they may.
    template <class It, class TriOf>
    bool covered(It begin, It end, TriOf&& tri_of, const Box& box, int axis, double cross_section) const {
        double quick = 0.0;
        for (It it = begin; it != end; ++it) quick += area_[tri_of(*it)];
        if (quick < cross_section * (1.0 - 1e-6)) return false;
        double exact = 0.0;
        for (It it = begin; it != end; ++it) exact += clipped_planar_area(scene_.triangle(tri_of(*it)), box, axis);
        return exact >= cross_section * (1.0 - 1e-6);
    }

    // Fills the tree's statistics once every node is written (the SAH cost relative to the root's area).
    void finish_stats();

private:
    void finish_leaf(const Box& box, std::size_t offset);

    const Scene& scene_;
    const KdBuildRules& rules_;
    const KdTree::Progress& progress_;
    KdTree::Impl& out_;
    std::vector<double> area_;
    std::size_t triangles_held_ = 0;
    double slack_ = 0.0;
    float scene_area_ = 0.0f;
    int max_depth_ = 0;
    double sah_cost_ = 0.0;  // sum of C_t x area over inner nodes and C_i x n x area over leaves
    double root_volume_ = 0.0, done_volume_ = 0.0, reported_ = 0.0;
};

}  // namespace beamtrace::kd
