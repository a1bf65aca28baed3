#include "kdtree/build_context.hpp"

#include <cmath>

#include "beamtrace/error.hpp"

namespace beamtrace::kd {

BuildContext::BuildContext(const Scene& scene, const KdBuildRules& rules, const KdTree::Progress& progress,
                           KdTree::Impl& out)
    : scene_(scene), rules_(rules), progress_(progress), out_(out) {
    out_.bounds = scene_.bounds();
    const Box& b = out_.bounds;
    double scale = b.diagonal();
    for (int k = 0; k < 3; ++k)
        scale = std::max({scale, double(std::fabs(b.lower[k])), double(std::fabs(b.upper[k]))});
    slack_ = std::ldexp(scale, -21);
    scene_area_ = b.surface_area();
    root_volume_ = b.volume();
    area_.resize(scene_.triangle_count());
}

void BuildContext::set_max_depth() {
    const double n = double(std::max<std::size_t>(triangles_held_, 1));
    max_depth_ = rules_.max_depth > 0 ? rules_.max_depth : std::min(60, int(8 + 1.3 * std::log2(n)));
    out_.nodes.reserve(2 * triangles_held_ + 1);
    out_.triangle_ids.reserve(2 * triangles_held_);
}

bool BuildContext::stops_here(const Box& box, std::size_t n, int depth) {
    if (out_.nodes.size() >= KdNode::kMaxIndex)
        throw Error("kd-tree: more than 2^30 nodes; the scene is too large for this tree");
    out_.stats.depth = std::max(out_.stats.depth, depth);
    if (n == 0 || n <= std::size_t(rules_.leaf_triangles) || depth >= max_depth_) return true;
    if (rules_.tiny_cell_rule && box.surface_area() < rules_.tiny_cell_min_area_fraction * scene_area_) {
        ++out_.stats.tiny_cell_leaves;
        return true;
    }
    return false;
}

void BuildContext::finish_leaf(const Box& box, std::size_t offset) {
    const std::size_t count = out_.triangle_ids.size() - offset;
    if (offset > KdNode::kMaxIndex || out_.triangle_ids.size() > std::size_t(KdNode::kMaxIndex))
        throw Error("kd-tree: more than 2^30 triangle references; the scene is too large for this tree");
    out_.nodes.push_back(KdNode::leaf(std::uint32_t(offset), std::uint32_t(count)));
    sah_cost_ += rules_.intersection_cost * double(count) * double(box.surface_area());
    KdBuildStats& s = out_.stats;
    ++s.leaves;
    if (count == 0) ++s.empty_leaves;
    if (box.lower.x == box.upper.x || box.lower.y == box.upper.y || box.lower.z == box.upper.z) ++s.flat_leaves;
    if (progress_ && root_volume_ > 0.0) {
        done_volume_ += double(box.volume());
        const double fraction = std::min(1.0, done_volume_ / root_volume_);
        if (fraction - reported_ >= 0.01) {
            reported_ = fraction;
            progress_(fraction);
        }
    }
}

void BuildContext::finish_stats() {
    KdBuildStats& s = out_.stats;
    s.triangles = scene_.triangle_count();
    s.degenerate_triangles = scene_.degenerate_count();
    s.nodes = out_.nodes.size();
    s.inner_nodes = s.nodes - s.leaves;
    s.triangle_references = out_.triangle_ids.size();
    const std::size_t full = s.leaves - s.empty_leaves;
    s.mean_triangles_per_leaf = full ? double(s.triangle_references) / double(full) : 0.0;
    s.sah_cost = scene_area_ > 0.0f ? sah_cost_ / double(scene_area_) : 0.0;
}

}  // namespace beamtrace::kd
