#include "mlrta/entry_point_search.hpp"

#include <algorithm>

#include "mlrta/beam_triangles.hpp"
#include "mlrta/direct_frustum_cull.hpp"
#include "mlrta/inverse_frustum_cull.hpp"

namespace beamtrace::mlrta {

namespace {

constexpr int kStackSize = SearchTrail::kCapacity;

class Search {
public:
    Search(const Mlrta::Impl& m, const Beam& beam, std::uint64_t& steps)
        : m_(m), kd_(m.kd()), rows_(m.packets.tables.rows()), beam_(beam), steps_(steps) {
        if (m.settings.experimental.frustum_test == FrustumTest::direct) frustum_ = make_frustum(beam);
        if (m.settings.experimental.ep_triangles) triangles_ = beam_frustum(beam);
    }

    // A blocker known from the parent tile (whose beam holds this one) blocks this beam as well:
    // it bounds the search from the start.
    void inherit(const EntryPoint& start) {
        if (start.blocked() && triangles_.valid)
            try_blocker(start.blocker, kd_.scene.triangle(start.blocker), start.box);
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

    // A leaf with triangles whose box the beam may meet and, for a beam with one origin, with at
    // least one triangle inside the beam's frustum.
    bool potential_leaf(const NodeBox& n) const {
        const KdNode& node = kd_.nodes[n.node];
        const std::uint32_t count = node.triangle_count();
        if (count == 0) return false;
        if (frustum_.valid ? frustum_misses_box(frustum_, n.box) : beam_misses_box(beam_, n.box)) return false;
        if (!triangles_.valid) return true;
        for (std::uint32_t j = 0; j < count; j += 16) {
            const int batch = int(std::min<std::uint32_t>(16, count - j));
            const std::uint32_t all = batch == 16 ? 0xFFFFu : (1u << batch) - 1u;
            if (m_.kernels().frustum_cull(triangles_, rows_, node.offset() + j, batch) != all) return true;
        }
        return false;
    }

    // Looks at a potential leaf the search has reached: a triangle of it that every ray of the beam
    // hits within its segment bounds the search (nothing beyond its hits can be a closest hit, and
    // every ray is occluded). True when every ray ends in this leaf: such a triangle's hits all lie
    // inside it (termination (4) of the paper, first case), or the leaf is flat, completely covered
    // by its triangles and crossed by every ray within its segment.
    bool examine(const NodeBox& leaf) {
        if (triangles_.valid) {
            const KdNode& node = kd_.nodes[leaf.node];
            const std::uint32_t count = node.triangle_count();
            if (count <= kMaxBlockingCandidates) {
                const std::uint32_t* ids = kd_.triangle_ids.data() + node.offset();
                const Triangle* tris = kd_.leaf_triangles.data() + node.offset();
                const std::uint32_t culled = m_.kernels().frustum_cull(triangles_, rows_, node.offset(), int(count));
                for (std::uint32_t j = 0; j < count; ++j)
                    if (!((culled >> j) & 1u) && try_blocker(ids[j], tris[j], leaf.box)) return true;
            }
        }
        return covered_flat_leaf_ends_all(leaf);
    }

    std::uint32_t blocker() const { return blocker_; }

    // Depth first (near child first) below `root`: the first leaf with potential intersections, if
    // any. `resume`: the trail of a search for a beam holding this one, whose walk below the same
    // `root` found its `second` leaf with `rest` still to visit: every leaf before that one holds
    // nothing for this beam either, so the walk starts there. `out` receives this walk's leaf and rest.
    bool first_potential_leaf(const NodeBox& root, NodeBox& leaf, const SearchTrail* resume = nullptr,
                              SearchTrail* out = nullptr) {
        Uninitialised<NodeBox, kStackSize> pending;
        NodeBox* stack = pending.at;
        int top = 0;
        if (resume) {
            for (; top < resume->pending; ++top) stack[top] = resume->rest.at[top];
            stack[top++] = resume->second;
        } else {
            stack[top++] = root;
        }
        while (top > 0) {
            const NodeBox n = stack[--top];
            ++steps_;
            if (kd_.nodes[n.node].is_leaf()) {
                if (potential_leaf(n)) {
                    leaf = n;
                    if (out) {
                        out->second_valid = true;
                        out->second = n;
                        out->pending = top;
                        for (int i = 0; i < top; ++i) out->rest.at[i] = stack[i];
                    }
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

    // Depth first from `n` (near child first) until the first leaf with potential intersections,
    // stacking the bifurcations on the way above those already on `bif`. False if there is none.
    bool descend(NodeBox n, Bifurcation* bif, int& top, NodeBox& leaf) {
        for (;;) {
            ++steps_;
            if (kd_.nodes[n.node].is_leaf()) {
                if (potential_leaf(n)) {
                    leaf = n;
                    return true;
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
            if (top == 0) return false;
            n = bif[--top].other;
        }
    }

    // Step 1 of the paper: depth first from `start` until the first leaf with potential
    // intersections, stacking the bifurcations (nodes whose both children the beam may enter, with
    // the child not yet searched) on the way. False if there is no such leaf at all.
    //
    // With the trail of the search for a beam holding this one (which started at `start`'s node),
    // the walk starts at that search's first potential leaf: every leaf before it holds nothing for
    // the larger beam, so nothing for this one, and the depth-first order is the same (one sign per
    // axis). Only the trail's bifurcations are decided again for this beam (one step each); where
    // this beam leaves the trail's path, the walk goes on from there as it would have.
    bool first_candidate(const EntryPoint& start, const SearchTrail* trail, Bifurcation* bif, int& top, NodeBox& leaf) {
        top = 0;
        if (!trail) return descend(NodeBox{start.node, start.box}, bif, top, leaf);
        for (int i = 0; i < trail->count; ++i) {
            const Bifurcation& b = trail->bif.at[i];
            ++steps_;
            NodeBox kids[2];
            const int c = children(b.node, kids);
            if (c == 2) {
                bif[top++] = Bifurcation{b.node, kids[1]};
                continue;
            }
            if (c == 1 && kids[0].node != b.other.node) continue;  // only the child on the path
            if (c == 1) return descend(kids[0], bif, top, leaf);   // only the other child
            if (top == 0) return false;                            // neither
            const NodeBox next = bif[--top].other;
            return descend(next, bif, top, leaf);
        }
        return descend(trail->first, bif, top, leaf);
    }

    // Steps 1-3 of the paper with the bifurcation stack, in the paper's order.
    EntryPoint run_bifurcation_stack(const EntryPoint& start, const SearchTrail* trail, SearchTrail* out) {
        Bifurcation* bif = work_.at;
        int top = 0;
        NodeBox candidate;
        if (!first_candidate(start, trail, bif, top, candidate)) return none(start);
        const NodeBox first = candidate;
        const int path = top;
        int from = path;  // the candidate's place on the stack (path: the first leaf itself)
        if (examine(candidate)) return entry(candidate);
        // Steps 2-3: the stacked nodes from the top; a potential leaf in the other subtree makes the
        // node the candidate.
        while (top > 0) {
            const Bifurcation& b = bif[--top];
            NodeBox leaf;
            if (first_potential_leaf(b.other, leaf, resumable(trail, b), out)) {
                candidate = b.node;
                from = top;
                if (!blocked()) examine(leaf);
            }
        }
        record(out, first, bif + from, path - from);
        return entry(candidate);
    }

    // The same entry point with fewer steps. The paper's steps 1-3 find the first potential leaf L
    // depth first, stack the bifurcations on the way, and then pop them deepest first, each
    // becoming the candidate when its other subtree holds a potential leaf: the result is the
    // *shallowest* stacked node with a potential leaf on its other side, or L. This walk finds L
    // the same way (step 1), then checks the stacked nodes shallowest first and stops at the first
    // whose other subtree holds a potential leaf: the deeper ones need no search. Termination (4)
    // is checked at L; a blocker found at L shortens the beam, so the other subtrees beyond it are
    // culled at their roots.
    EntryPoint run_top_down(const EntryPoint& start, const SearchTrail* trail, SearchTrail* out) {
        Bifurcation* bif = work_.at;
        int top = 0;
        NodeBox first;
        if (!first_candidate(start, trail, bif, top, first)) return none(start);
        if (examine(first)) return entry(first);
        for (int i = 0; i < top; ++i) {  // the bifurcations on L's path, shallowest first
            NodeBox leaf;
            if (first_potential_leaf(bif[i].other, leaf, resumable(trail, bif[i]), out)) {
                if (!blocked()) examine(leaf);
                record(out, first, bif + i, top - i);
                return entry(bif[i].node);
            }
        }
        return entry(first);
    }

private:
    bool blocked() const { return blocker_ != kNoHit; }

    // The trail for searches of parts of this beam: the first potential leaf and the bifurcations
    // on its path from the entry point (bif[0]) down.
    void record(SearchTrail* out, const NodeBox& first, const Bifurcation* bif, int count) const {
        if (!out) return;
        out->valid = true;
        for (int k = 0; k < 3; ++k) out->sign[k] = beam_.sign[k];
        out->first = first;
        out->count = count;
        for (int i = 0; i < count; ++i) out->bif.at[i] = bif[i];
    }

    // The trail, if its walk of the other subtree of its entry point is that of bifurcation `b`.
    static const SearchTrail* resumable(const SearchTrail* trail, const Bifurcation& b) {
        if (!trail || !trail->second_valid || trail->count == 0) return nullptr;
        return trail->bif.at[0].other.node == b.other.node ? trail : nullptr;
    }

    EntryPoint entry(const NodeBox& n) const {
        EntryPoint e{n.node, n.box, false};
        e.blocker = blocker_;
        return e;
    }
    EntryPoint none(const EntryPoint& start) const {
        EntryPoint e = start;
        e.misses = true;
        e.blocker = kNoHit;
        return e;
    }

    // Does triangle `id` block the beam? If so, and nearer than the blocker known so far, it becomes
    // the blocker and the beam's segments are cut at its farthest hit. True when its hits all lie
    // inside `cell`.
    bool try_blocker(std::uint32_t id, const Triangle& tri, const Box& cell) {
        const BeamBlock b = beam_block(beam_, triangles_, tri, cell);
        if (!b.blocks) return false;
        if (!blocked() || b.far < blocker_far_) {
            blocker_ = id;
            blocker_far_ = b.far;
            // Lengths are measured from the starts; the cut keeps a relative margin and rounds up.
            const double cut = (b.far - double(beam_.apex_near.lo)) * (1.0 + 1e-5);
            const float length = std::nextafter(float(cut), kInfinity);
            if (length < beam_.length.hi) beam_.length = {std::min(beam_.length.lo, length), length};
        }
        return b.inside;
    }

    bool covered_flat_leaf_ends_all(const NodeBox& n) const {
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

    const Mlrta::Impl& m_;
    const KdTree::Impl& kd_;
    kdtree::CornerRows rows_;  // the leaf triangles' corners, for the frustum culling
    Beam beam_;                // a copy: a blocker shortens its segments
    std::uint64_t& steps_;
    Frustum4 frustum_;
    OneOriginFrustum triangles_;  // valid for beams with one origin when settings.ep_triangles
    std::uint32_t blocker_ = kNoHit;
    double blocker_far_ = 0.0;
    // Leaves with more triangles are not searched for one that blocks the beam (a cost bound).
    static constexpr std::uint32_t kMaxBlockingCandidates = 16;
    Uninitialised<Bifurcation, kStackSize> work_;  // the bifurcation stack
};

}  // namespace

EntryPoint entry_point_search(const Mlrta::Impl& m, const Beam& beam, const EntryPoint& start, std::uint64_t& steps,
                              const SearchTrail* trail, SearchTrail* out) {
    if (out) out->valid = out->second_valid = false;
    if (trail && !trail->valid) trail = nullptr;
    Search search(m, beam, steps);
    search.inherit(start);
    return m.settings.experimental.ep_search == EpSearch::bifurcation_stack
               ? search.run_bifurcation_stack(start, trail, out)
               : search.run_top_down(start, trail, out);
}

}  // namespace beamtrace::mlrta
