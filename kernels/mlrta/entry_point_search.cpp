#include "mlrta/entry_point_search.hpp"

#include "mlrta/direct_frustum_cull.hpp"
#include "mlrta/inverse_frustum_cull.hpp"

namespace beamtrace::mlrta {

namespace {

constexpr int kStackSize = 64;

struct NodeBox {
    std::uint32_t node;
    Box box;
};

// The bifurcation stack: nodes whose both children the beam may enter, with the child not yet searched.
struct Bifurcation {
    NodeBox node;
    NodeBox other;
};

class Search {
public:
    Search(const Mlrta::Impl& m, const Beam& beam, std::uint64_t& steps)
        : m_(m), kd_(m.kd()), beam_(beam), steps_(steps) {
        if (m.settings.frustum_test == FrustumTest::direct) frustum_ = make_frustum(beam);
    }

    // Children of an inner node the beam may enter, near child first.
    int children(const NodeBox& n, NodeBox out[2]) const {
        const KdNode& node = kd_.nodes[n.node];
        const int k = node.axis();
        NodeBox lower{n.node + 1, n.box}, upper{node.upper_child(), n.box};
        lower.box.upper[k] = node.split;
        upper.box.lower[k] = node.split;
        bool lo, hi;
        if (frustum_.valid) {
            lo = !frustum_misses_box(frustum_, lower.box);
            hi = !frustum_misses_box(frustum_, upper.box);
        } else {
            const ChildMask mask = cull_split(beam_, n.box, k, node.split);
            lo = mask & kLower;
            hi = mask & kUpper;
        }
        const bool lower_first = beam_.sign[k] > 0;
        int count = 0;
        if (lower_first ? lo : hi) out[count++] = lower_first ? lower : upper;
        if (lower_first ? hi : lo) out[count++] = lower_first ? upper : lower;
        return count;
    }

    bool potential_leaf(const NodeBox& n) const {
        const KdNode& node = kd_.nodes[n.node];
        if (node.triangle_count() == 0) return false;
        return frustum_.valid ? !frustum_misses_box(frustum_, n.box) : !beam_misses_box(beam_, n.box);
    }

    // Every ray of the beam crosses this flat, completely covered leaf within its segment.
    bool all_rays_end_in(const NodeBox& n) const {
        if (!m_.covered_leaf[n.node]) return false;
        int k = 0;
        while (k < 3 && n.box.lower[k] != n.box.upper[k]) ++k;
        if (k == 3) return false;
        const float plane = n.box.lower[k];
        for (int j = 0; j < 3; ++j) {
            if (j == k) continue;
            const Interval r = beam_.plane_range(k, plane, j);
            if (r.lo < n.box.lower[j] || r.hi > n.box.upper[j]) return false;
        }
        const Interval t = beam_.plane_t(k, plane);
        return t.lo >= 0.0f && t.hi <= beam_.length.lo;
    }

    // Depth first (near child first) below `root`: the first leaf with potential intersections, if any.
    bool first_potential_leaf(const NodeBox& root, NodeBox& leaf) {
        NodeBox stack[kStackSize];
        int top = 0;
        stack[top++] = root;
        while (top > 0) {
            const NodeBox n = stack[--top];
            ++steps_;
            if (kd_.nodes[n.node].is_leaf()) {
                if (potential_leaf(n)) {
                    leaf = n;
                    return true;
                }
                continue;
            }
            NodeBox kids[2];
            const int c = children(n, kids);
            for (int i = c - 1; i >= 0; --i) stack[top++] = kids[i];  // near child on top
        }
        return false;
    }

    // Depth first below `root`: is there any leaf with potential intersections?
    bool any_potential_leaf(const NodeBox& root) {
        NodeBox leaf;
        return first_potential_leaf(root, leaf);
    }

    // Steps 1-3 of the paper with the bifurcation stack, in the paper's order.
    EntryPoint run_bifurcation_stack(const EntryPoint& start) {
        Bifurcation bif[kStackSize];
        int top = 0;
        NodeBox n{start.node, start.box};
        NodeBox candidate{};
        bool found = false;
        // Steps 1: depth first until the first leaf with potential intersections.
        for (;;) {
            ++steps_;
            const KdNode& node = kd_.nodes[n.node];
            if (node.is_leaf()) {
                if (potential_leaf(n)) {
                    candidate = n;
                    found = true;
                    if (all_rays_end_in(n)) return EntryPoint{n.node, n.box, false};
                    break;
                }
            } else {
                NodeBox kids[2];
                const int c = children(n, kids);
                if (c == 2) bif[top++] = Bifurcation{n, kids[1]};
                if (c > 0) {
                    n = kids[0];
                    continue;
                }
            }
            // A dead end: the last bifurcation had nothing in its near subtree; it is no longer one.
            if (top == 0) break;
            n = bif[--top].other;
        }
        if (!found) {
            EntryPoint none = start;
            none.misses = true;
            return none;
        }
        // Steps 2-3: the stacked nodes from the top; a potential leaf in the other subtree makes the
        // node the candidate.
        while (top > 0) {
            const Bifurcation& b = bif[--top];
            if (any_potential_leaf(b.other)) candidate = b.node;
        }
        return EntryPoint{candidate.node, candidate.box, false};
    }

    // The paper's steps 1-3 find the first potential leaf L depth first, stack the bifurcations on
    // the way, and then pop them deepest first, each becoming the candidate when its other subtree
    // holds a potential leaf: the result is the *shallowest* stacked node with potential leaves on
    // both sides, or L. This walk finds the same node top down, so it can stop at the first such
    // node instead of searching below every deeper one: from the start, follow single children;
    // at a node with two possible children, search the near one for a potential leaf (the first
    // one found overall is L, where termination (4) is checked), then the far one; both: that node
    // is the entry point; one: continue into it; none: the beam misses everything.
    EntryPoint run_top_down(const EntryPoint& start) {
        NodeBox n{start.node, start.box};
        bool first_leaf_seen = false;
        auto at_first_leaf = [&](const NodeBox& leaf) {
            const bool ends = !first_leaf_seen && all_rays_end_in(leaf);
            first_leaf_seen = true;
            return ends;
        };
        for (;;) {
            ++steps_;
            if (kd_.nodes[n.node].is_leaf()) {
                if (!potential_leaf(n)) break;
                at_first_leaf(n);
                return EntryPoint{n.node, n.box, false};
            }
            NodeBox kids[2];
            const int c = children(n, kids);
            if (c == 0) break;
            if (c == 1) {
                n = kids[0];
                continue;
            }
            NodeBox leaf;
            if (!first_potential_leaf(kids[0], leaf)) {
                n = kids[1];
                continue;
            }
            if (at_first_leaf(leaf)) return EntryPoint{leaf.node, leaf.box, false};
            if (!first_potential_leaf(kids[1], leaf)) {
                n = kids[0];
                continue;
            }
            return EntryPoint{n.node, n.box, false};
        }
        EntryPoint none = start;
        none.misses = true;
        return none;
    }

private:
    const Mlrta::Impl& m_;
    const KdTree::Impl& kd_;
    const Beam& beam_;
    std::uint64_t& steps_;
    Frustum4 frustum_;
};

}  // namespace

EntryPoint entry_point_search(const Mlrta::Impl& m, const Beam& beam, const EntryPoint& start, std::uint64_t& steps) {
    Search search(m, beam, steps);
    return m.settings.ep_search == EpSearch::bifurcation_stack ? search.run_bifurcation_stack(start)
                                                               : search.run_top_down(start);
}

}  // namespace beamtrace::mlrta
