// O(N log N) SAH kd-tree build (Wald & Havran 2006: events sorted once, split lists kept sorted,
// straddling triangles clipped into both children) with the construction rules of MLRTA section 3.1:
//   rule 1: cut off an empty cell of at least `empty_cell_min_volume_fraction` of the parent volume;
//   rule 2: take a split plane completely covered by coplanar triangles, which go to the smaller side;
//   rule 3: make a leaf instead of splitting cells whose area is tiny relative to the scene's box.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "beamtrace/error.hpp"
#include "kdtree/kd_node.hpp"
#include "kdtree/split_events.hpp"

namespace beamtrace {
namespace kd {
namespace {

enum Side : std::uint8_t { kLeft = 0, kRight = 1, kBoth = 2 };
enum class Rule { sah, empty_cell, flat_cell };

// Bonus of the classic SAH for splits with an empty side (Wald & Havran's lambda).
constexpr float kEmptySideBonus = 0.8f;

struct SplitChoice {
    int axis = -1;
    float pos = 0.0f;
    bool planar_left = false;
    float cost = INFINITY;
    Rule rule = Rule::sah;
};

std::size_t triangles_in(const AxisEvents& events) {
    std::size_t n = 0;
    for (const SplitEvent& e : events) n += e.type() != kEnd;
    return n;
}

class SahBuilder {
public:
    SahBuilder(const Scene& scene, const KdBuildRules& rules, const KdTree::Progress& progress, KdTree::Impl& out)
        : scene_(scene), rules_(rules), progress_(progress), out_(out) {}

    void run() {
        const std::size_t count = scene_.triangle_count();
        if (count > kd::SplitEvent::kMaxTriangle)
            throw Error("kd-tree: " + std::to_string(count) + " triangles exceed the tree's limit of 2^30");
        out_.bounds = scene_.bounds();
        const Box& b = out_.bounds;
        double scale = b.diagonal();
        for (int k = 0; k < 3; ++k)
            scale = std::max({scale, double(std::fabs(b.lower[k])), double(std::fabs(b.upper[k]))});
        slack_ = std::ldexp(scale, -21);
        scene_area_ = b.surface_area();
        root_volume_ = b.volume();
        side_.assign(count, kBoth);
        area_.resize(count);

        AxisEvents events[3];
        for (auto& e : events) e.reserve(2 * count);
        std::size_t n = 0;
        for (std::uint32_t t = 0; t < count; ++t) {
            if (scene_.is_degenerate(t)) continue;
            const Triangle& tri = scene_.triangle(t);
            area_[t] = 0.5 * length(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
            Box tb;
            tb.extend(tri.v0);
            tb.extend(tri.v1);
            tb.extend(tri.v2);
            append_events(t, tb, events);
            ++n;
        }
        for (auto& e : events) sort_events(e, scratch_);

        max_depth_ = rules_.max_depth > 0 ? rules_.max_depth
                                          : std::min(60, int(8 + 1.3 * std::log2(double(std::max<std::size_t>(n, 1)))));
        out_.nodes.reserve(2 * n + 1);
        out_.triangle_ids.reserve(2 * n);
        build_node(b, events, n, 0);

        KdBuildStats& s = out_.stats;
        s.triangles = count;
        s.degenerate_triangles = scene_.degenerate_count();
        s.nodes = out_.nodes.size();
        s.inner_nodes = s.nodes - s.leaves;
        s.triangle_references = out_.triangle_ids.size();
        const std::size_t full = s.leaves - s.empty_leaves;
        s.mean_triangles_per_leaf = full ? double(s.triangle_references) / double(full) : 0.0;
        out_.gather_leaf_triangles();
        s.bytes = out_.nodes.size() * sizeof(KdNode) + out_.triangle_ids.size() * sizeof(std::uint32_t) +
                  out_.leaf_triangles.size() * sizeof(Triangle);
        if (progress_) progress_(1.0);
    }

private:
    void build_node(const Box& box, AxisEvents (&events)[3], std::size_t n, int depth) {
        if (out_.nodes.size() >= KdNode::kMaxIndex)
            throw Error("kd-tree: more than 2^30 nodes; the scene is too large for this tree");
        out_.stats.depth = std::max(out_.stats.depth, depth);
        if (n == 0 || n <= std::size_t(rules_.leaf_triangles) || depth >= max_depth_) {
            make_leaf(box, events[0]);
            return;
        }
        if (rules_.tiny_cell_rule && box.surface_area() < rules_.tiny_cell_min_area_fraction * scene_area_) {
            ++out_.stats.tiny_cell_leaves;
            make_leaf(box, events[0]);
            return;
        }
        const SplitChoice split = find_split(box, events, n);
        if (split.axis < 0) {
            make_leaf(box, events[0]);
            return;
        }
        if (split.rule == Rule::empty_cell) ++out_.stats.empty_cell_splits;
        if (split.rule == Rule::flat_cell) ++out_.stats.flat_cell_splits;

        Box left = box, right = box;
        left.upper[split.axis] = split.pos;
        right.lower[split.axis] = split.pos;
        AxisEvents left_events[3], right_events[3];
        partition(split, left, right, events, left_events, right_events);
        const std::size_t nl = triangles_in(left_events[0]), nr = triangles_in(right_events[0]);

        const std::size_t index = out_.nodes.size();
        out_.nodes.push_back(KdNode::leaf(0, 0));
        build_node(left, left_events, nl, depth + 1);
        for (auto& e : left_events) AxisEvents().swap(e);
        out_.nodes[index] = KdNode::inner(split.axis, split.pos, std::uint32_t(out_.nodes.size()));
        build_node(right, right_events, nr, depth + 1);
    }

    SplitChoice find_split(const Box& box, const AxisEvents (&events)[3], std::size_t n) const {
        const float area = box.surface_area();
        const float ct = rules_.traversal_cost, ci = rules_.intersection_cost;
        SplitChoice best_sah, best_flat;
        SplitChoice best_empty;
        float best_empty_fraction = 0.0f;
        best_empty.cost = 0.0f;

        for (int k = 0; k < 3; ++k) {
            const float lo = box.lower[k], hi = box.upper[k];
            if (!(hi > lo)) continue;  // flat along k: no plane splits it
            const int u = (k + 1) % 3, v = (k + 2) % 3;
            const float eu = box.upper[u] - box.lower[u], ev_ = box.upper[v] - box.lower[v];
            const double cross_section = double(eu) * double(ev_);
            // Child areas relative to the parent's: length along k times a, plus b.
            const float a = 2.0f * (eu + ev_) / area, b = 2.0f * eu * ev_ / area;
            const AxisEvents& ev = events[k];
            std::size_t nl = 0, nr = n;
            std::size_t i = 0;
            while (i < ev.size()) {
                const float p = ev[i].pos;
                std::size_t ends = 0, planars = 0, starts = 0;
                while (i < ev.size() && ev[i].pos == p && ev[i].type() == kEnd) ++ends, ++i;
                const std::size_t planar_begin = i;
                while (i < ev.size() && ev[i].pos == p && ev[i].type() == kPlanar) ++planars, ++i;
                const std::size_t planar_end = i;
                while (i < ev.size() && ev[i].pos == p && ev[i].type() == kStart) ++starts, ++i;
                const std::size_t np = planars;
                nr -= planars + ends;

                const bool at_lower = !(p > lo), at_upper = !(p < hi);
                if (!(at_lower || at_upper) || np > 0) {
                    const float pl = (p - lo) * a + b, pr = (hi - p) * a + b;
                    auto cost_of = [&](std::size_t a, std::size_t b) {
                        const float c = ct + ci * (pl * float(a) + pr * float(b));
                        return (a == 0 || b == 0) ? c * kEmptySideBonus : c;
                    };
                    if (!at_upper) {  // planar triangles to the left
                        const float c = cost_of(nl + np, nr);
                        if (c < best_sah.cost) best_sah = SplitChoice{k, p, true, c, Rule::sah};
                    }
                    if (!at_lower) {  // planar triangles to the right
                        const float c = cost_of(nl, nr + np);
                        if (c < best_sah.cost) best_sah = SplitChoice{k, p, false, c, Rule::sah};
                    }
                    if (!at_lower && !at_upper) {
                        const float left_empty = (p - lo) / (hi - lo), right_empty = (hi - p) / (hi - lo);
                        if (nl == 0 && left_empty > best_empty_fraction) {
                            best_empty_fraction = left_empty;
                            best_empty = SplitChoice{k, p, false, 0.0f, Rule::empty_cell};
                        }
                        if (nr == 0 && right_empty > best_empty_fraction) {
                            best_empty_fraction = right_empty;
                            best_empty = SplitChoice{k, p, true, 0.0f, Rule::empty_cell};
                        }
                    }
                    if (np > 0 && rules_.flat_cell_rule && cross_section > 0.0 &&
                        covered(ev, planar_begin, planar_end, box, k, cross_section)) {
                        const bool to_left = at_lower || (!at_upper && p - lo <= hi - p);
                        const float c = to_left ? cost_of(nl + np, nr) : cost_of(nl, nr + np);
                        if (c < best_flat.cost) best_flat = SplitChoice{k, p, to_left, c, Rule::flat_cell};
                    }
                }
                nl += starts + planars;
            }
        }
        if (rules_.empty_cell_rule && best_empty.axis >= 0 &&
            best_empty_fraction >= rules_.empty_cell_min_volume_fraction)
            return best_empty;
        if (best_flat.axis >= 0) return best_flat;
        if (best_sah.axis >= 0 && best_sah.cost < ci * float(n)) return best_sah;
        return SplitChoice{};
    }

    // True if the planar triangles at one position cover the cell's whole cross-section.
    bool covered(const AxisEvents& ev, std::size_t begin, std::size_t end, const Box& box, int axis,
                 double cross_section) const {
        double quick = 0.0;
        for (std::size_t j = begin; j < end; ++j) quick += area_[ev[j].tri()];
        if (quick < cross_section * (1.0 - 1e-6)) return false;
        double exact = 0.0;
        for (std::size_t j = begin; j < end; ++j) exact += clipped_planar_area(scene_.triangle(ev[j].tri()), box, axis);
        return exact >= cross_section * (1.0 - 1e-6);
    }

    void partition(const SplitChoice& s, const Box& left, const Box& right, AxisEvents (&events)[3],
                   AxisEvents (&left_events)[3], AxisEvents (&right_events)[3]) {
        // One pass over the split axis classifies every triangle: a start at or above the plane is
        // right only, an end at or below it left only (its start came earlier), otherwise both;
        // triangles still "both" at their end event straddle the plane.
        both_.clear();
        for (const SplitEvent& e : events[s.axis]) {
            const std::uint32_t t = e.tri();
            switch (e.type()) {
                case kStart:
                    side_[t] = e.pos >= s.pos ? kRight : kBoth;
                    break;
                case kPlanar:
                    side_[t] = (e.pos < s.pos || (e.pos == s.pos && s.planar_left)) ? kLeft : kRight;
                    break;
                case kEnd:
                    if (e.pos <= s.pos)
                        side_[t] = kLeft;
                    else if (side_[t] == kBoth)
                        both_.push_back(t);
                    break;
            }
        }
        for (int k = 0; k < 3; ++k) {
            left_events[k].reserve(events[k].size() / 2 + 2 * both_.size());
            right_events[k].reserve(events[k].size() / 2 + 2 * both_.size());
            for (const SplitEvent& e : events[k]) {
                if (side_[e.tri()] == kLeft)
                    left_events[k].push_back(e);
                else if (side_[e.tri()] == kRight)
                    right_events[k].push_back(e);
            }
            AxisEvents().swap(events[k]);
        }
        if (both_.empty()) return;
        AxisEvents new_left[3], new_right[3];
        for (std::uint32_t t : both_) {
            const Triangle& tri = scene_.triangle(t);
            const Box bl = clipped_bounds(tri, left, slack_);
            if (!bl.empty()) append_events(t, bl, new_left);
            const Box br = clipped_bounds(tri, right, slack_);
            if (!br.empty()) append_events(t, br, new_right);
        }
        for (int k = 0; k < 3; ++k) {
            merge_into(left_events[k], new_left[k]);
            merge_into(right_events[k], new_right[k]);
        }
    }

    void merge_into(AxisEvents& kept, AxisEvents& added) {
        if (added.empty()) return;
        sort_events(added, scratch_);
        const std::size_t mid = kept.size();
        kept.insert(kept.end(), added.begin(), added.end());
        std::inplace_merge(kept.begin(), kept.begin() + std::ptrdiff_t(mid), kept.end());
    }

    void make_leaf(const Box& box, const AxisEvents& axis0) {
        const std::size_t offset = out_.triangle_ids.size();
        for (const SplitEvent& e : axis0)
            if (e.type() != kEnd) out_.triangle_ids.push_back(e.tri());
        const std::size_t count = out_.triangle_ids.size() - offset;
        std::sort(out_.triangle_ids.begin() + std::ptrdiff_t(offset), out_.triangle_ids.end());
        if (offset > KdNode::kMaxIndex || out_.triangle_ids.size() > std::size_t(KdNode::kMaxIndex))
            throw Error("kd-tree: more than 2^30 triangle references; the scene is too large for this tree");
        out_.nodes.push_back(KdNode::leaf(std::uint32_t(offset), std::uint32_t(count)));
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

    const Scene& scene_;
    const KdBuildRules& rules_;
    const KdTree::Progress& progress_;
    KdTree::Impl& out_;
    std::vector<std::uint8_t> side_;
    std::vector<double> area_;
    std::vector<std::uint32_t> both_;
    AxisEvents scratch_;  // of sort_events
    double slack_ = 0.0;
    float scene_area_ = 0.0f;
    int max_depth_ = 0;
    double root_volume_ = 0.0, done_volume_ = 0.0, reported_ = 0.0;
};

}  // namespace
}  // namespace kd

KdTree KdTree::build(const Scene& scene, const KdBuildRules& rules, const Progress& progress) {
    rules.validate();
    const auto start = std::chrono::steady_clock::now();
    auto impl = std::make_shared<Impl>(scene);
    impl->kernels = &triangle_kernels();
    kd::SahBuilder(scene, rules, progress, *impl).run();
    impl->stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return KdTree(std::move(impl));
}

const Scene& KdTree::scene() const { return impl_->scene; }
const KdBuildStats& KdTree::stats() const { return impl_->stats; }

}  // namespace beamtrace
