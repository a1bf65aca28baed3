#pragma once
// The binned upper levels of the hybrid SAH build (KdBuildRules::binned_above): a cell holding
// more triangle references than that finds its split among bin boundaries (KdBuildRules::bins per
// axis, from histograms of where the references' boxes start and end: reference_bins.hpp) and its
// references' tight bounds, instead of sorting and sweeping every event; the references crossing the plane are
// clipped into both children as the exact build clips them. A cell at or below the threshold (or
// for which no boundary is worth a split) gets its event lists made from its references' boxes,
// sorted, and is built by the exact event sweep (event_sweep_builder.hpp).
#include <cstdint>
#include <vector>

#include "kdtree/build_context.hpp"
#include "kdtree/event_sweep_builder.hpp"
#include "kdtree/reference_bins.hpp"

namespace beamtrace::kd {

class BinnedBuilder {
public:
    // binned_above 0 hands every cell, the root first, to the exact sweep.
    BinnedBuilder(BuildContext& context, EventSweepBuilder& exact);

    // Writes the subtree of a cell holding `refs` (used up).
    void build(const Box& box, CellReferences& refs, int depth);

private:
    void hand_over(const Box& box, CellReferences& refs, int depth);
    SplitChoice find_split(const Box& box, const CellReferences& refs) const;
    void partition(const SplitChoice& s, const Box& left, const Box& right, CellReferences& refs,
                   CellReferences& left_refs, CellReferences& right_refs) const;

    BuildContext& context_;
    EventSweepBuilder& exact_;
    std::size_t binned_above_;
    int bins_;
};

}  // namespace beamtrace::kd
