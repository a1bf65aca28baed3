#include "kdtree/binned_builder.hpp"

#include <algorithm>
#include <limits>
#include <utility>

namespace beamtrace::kd {

BinnedBuilder::BinnedBuilder(BuildContext& context, EventSweepBuilder& exact)
    : context_(context),
      exact_(exact),
      binned_above_(context.rules().binned_above > 0 ? std::size_t(context.rules().binned_above)
                                                     : std::numeric_limits<std::size_t>::max()),
      bins_(context.rules().bins) {}

void BinnedBuilder::build(const Box& box, CellReferences& refs, int depth) {
    const std::size_t n = refs.list.size();
    if (n <= binned_above_) return hand_over(box, refs, depth);
    if (context_.stops_here(box, n, depth)) {
        context_.make_leaf(box, [&](std::vector<std::uint32_t>& ids) {
            for (const CellReference& r : refs.list) ids.push_back(r.tri);
        });
        return;
    }
    const SplitChoice split = find_split(box, refs);
    if (split.axis < 0) return hand_over(box, refs, depth);  // the exact sweep may still find a plane

    Box left = box, right = box;
    left.upper[split.axis] = split.pos;
    right.lower[split.axis] = split.pos;
    CellReferences left_refs, right_refs;
    partition(split, left, right, refs, left_refs, right_refs);
    context_.count_binned_split();
    context_.make_inner(
        split, box,
        [&] {
            build(left, left_refs, depth + 1);
            left_refs = CellReferences();
        },
        [&] { build(right, right_refs, depth + 1); });
}

void BinnedBuilder::hand_over(const Box& box, CellReferences& refs, int depth) {
    AxisEvents events[3];
    for (auto& e : events) e.reserve(2 * refs.list.size());
    for (const CellReference& r : refs.list) append_events(r.tri, r.box, events);
    const std::size_t n = refs.list.size();
    refs = CellReferences();
    exact_.sort(events);
    exact_.build(box, events, n, depth);
}

SplitChoice BinnedBuilder::find_split(const Box& box, const CellReferences& refs) const {
    const Box& tight = refs.bounds;
    if (const SplitChoice cut = empty_cell_cut(context_.rules(), box, tight); cut.axis >= 0) return cut;

    ReferenceBins bins(box, tight, bins_);
    for (const CellReference& r : refs.list) bins.add(r);

    const std::size_t n = refs.list.size();
    const float area = box.surface_area();
    SplitSearch search(context_.rules());
    for (int k = 0; k < 3; ++k) {
        const AxisCell cell(box, k, area);
        if (!cell.splittable()) continue;
        // Rule 2's test of a plane: the references lying in it, gathered only when their whole
        // areas could cover the face (of float areas: a looser first test than covered()'s).
        auto covered_at = [&](float p, const ReferenceBins::InPlane& in) {
            return [&, p] {
                if (in.area < cell.cross_section * (1.0 - 1e-4)) return false;
                std::vector<std::uint32_t> in_plane;
                for (const CellReference& r : refs.list)
                    if (r.box.lower[k] == p && r.box.upper[k] == p) in_plane.push_back(r.tri);
                return context_.covered(in_plane.begin(), in_plane.end(), [](std::uint32_t t) { return t; }, box, k,
                                        cell.cross_section);
            };
        };
        // The tight bounds, exact: the faces' flat cells and the largest empty cells.
        const float lowest = tight.lower[k], highest = tight.upper[k];
        const ReferenceBins::InPlane &at_lowest = bins.at_lowest(k), &at_highest = bins.at_highest(k);
        search.consider(cell, lowest, 0, at_lowest.count, n - at_lowest.count, covered_at(lowest, at_lowest));
        search.consider(cell, highest, n - at_highest.count, at_highest.count, 0, covered_at(highest, at_highest));
        // The boundaries, with the counts of the bins (a reference in a boundary's plane counted
        // on the side its bin says); a side is empty exactly when the tight bounds say so.
        std::size_t nl = 0, nr = n;
        for (int i = 1; i < bins.bins(); ++i) {
            nl += bins.starts(k, i - 1);
            nr -= bins.ends(k, i - 1);
            const float p = bins.boundary(k, i);
            const std::size_t left = lowest >= p ? 0 : std::max<std::size_t>(nl, 1);
            const std::size_t right = highest <= p ? 0 : std::max<std::size_t>(nr, 1);
            search.consider(cell, p, left, 0, right, [] { return false; });
        }
    }
    return search.choice(n);
}

void BinnedBuilder::partition(const SplitChoice& s, const Box& left, const Box& right, CellReferences& refs,
                              CellReferences& left_refs, CellReferences& right_refs) const {
    if (s.rule == Rule::empty_cell) {  // every reference on the side the plane's triangles go to
        (s.planar_left ? left_refs : right_refs) = std::move(refs);
        return;
    }
    // As the exact sweep classifies events: in the plane by planar_left, starting at or above it
    // right only, ending at or below it left only, otherwise both (clipped to each side). The upper
    // side keeps the cell's list, written over from its front (never past the reference read); the
    // lower side's list gets room for all (pages it does not reach are never touched).
    const int k = s.axis;
    std::vector<CellReference>& list = refs.list;
    left_refs.list.reserve(list.size());
    Box& kept_bounds = right_refs.bounds;
    std::size_t kept = 0;
    auto keep = [&](const CellReference& r) {
        list[kept++] = r;
        kept_bounds.extend(r.box);
    };
    for (std::size_t i = 0; i < list.size(); ++i) {
        const CellReference r = list[i];
        const float l = r.box.lower[k], u = r.box.upper[k];
        if (l == u ? l < s.pos || (l == s.pos && s.planar_left) : u <= s.pos) {
            left_refs.add(r);
        } else if (l >= s.pos) {
            keep(r);
        } else {
            const Triangle& tri = context_.scene().triangle(r.tri);
            const Box bl = clipped_bounds(tri, left, context_.slack());
            if (!bl.empty()) left_refs.add(CellReference{bl, r.tri, r.area});
            const Box br = clipped_bounds(tri, right, context_.slack());
            if (!br.empty()) keep(CellReference{br, r.tri, r.area});
        }
    }
    list.resize(kept);
    right_refs.list = std::move(list);
    refs = CellReferences();
}

}  // namespace beamtrace::kd
