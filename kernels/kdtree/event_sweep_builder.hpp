#pragma once
// The exact O(N log N) SAH build of a subtree (Wald & Havran 2006): a cell's split candidates are
// every event of its three sorted event lists, swept once per node; the lists of the one-sided
// triangles stay sorted when handed to the children, triangles crossing the plane are clipped into
// both and their new events merged in. The whole tree when KdBuildRules::binned_above is 0, else
// the subtrees below the binned levels (binned_builder.hpp).
#include <cstdint>
#include <vector>

#include "kdtree/build_context.hpp"
#include "kdtree/split_events.hpp"

namespace beamtrace::kd {

class EventSweepBuilder {
public:
    explicit EventSweepBuilder(BuildContext& context);

    // Writes the subtree of a cell whose n triangles have the sorted events `events` (used up).
    void build(const Box& box, AxisEvents (&events)[3], std::size_t n, int depth);

    // Sorts lists of events made in any order (scratch reused across calls).
    void sort(AxisEvents (&events)[3]);

private:
    SplitChoice find_split(const Box& box, const AxisEvents (&events)[3], std::size_t n) const;
    void partition(const SplitChoice& s, const Box& left, const Box& right, AxisEvents (&events)[3],
                   AxisEvents (&left_events)[3], AxisEvents (&right_events)[3]);
    void merge_into(AxisEvents& kept, AxisEvents& added);

    BuildContext& context_;
    std::vector<std::uint8_t> side_;  // of each triangle, while a node is partitioned
    std::vector<std::uint32_t> both_;
    AxisEvents scratch_;  // of sort_events
};

}  // namespace beamtrace::kd
