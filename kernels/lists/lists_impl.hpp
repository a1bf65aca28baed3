#pragma once
// The state of a SortedLists (sorted_lists.hpp): the volumes of the hierarchy and, per volume, the
// paper's three event lists over its direct children, each kept as its two halves (the lower and the
// upper coordinates, each sorted) so that a ray takes its IN and its OUT events from separate runs.
#include <cstdint>
#include <vector>

#include "beamtrace/sorted_lists.hpp"

namespace beamtrace {

namespace lists {

// One event: a child's coordinate on one axis. Items below the scene's triangle count are triangles
// (their id); item triangle_count + v is volume v.
struct Event {
    float value;
    std::uint32_t item;
};

// A volume: the union of its children's boxes and their 6 sorted runs in Impl::events, from `first`:
// axis a's lower coordinates at first + (2a) * children, its upper ones at first + (2a + 1) * children,
// each ascending (at equal value, by item).
struct Volume {
    Box box;
    std::uint32_t first = 0;
    std::uint32_t children = 0;
    std::uint32_t depth = 0;  // the root is 0

    std::uint32_t run(int axis, int upper) const { return first + std::uint32_t(2 * axis + upper) * children; }
};

}  // namespace lists

struct SortedLists::Impl {
    Impl(const Scene& s, const SortedListRules& r) : scene(s), rules(r) {}
    Scene scene;
    SortedListRules rules;
    SortedListStats stats;
    std::uint32_t triangle_count = 0;    // the scene's (degenerate ones included): the first volume item
    std::vector<lists::Volume> volumes;  // volume 0 is the root
    std::vector<lists::Event> events;

    std::uint32_t item_count() const { return triangle_count + std::uint32_t(volumes.size()); }
};

namespace lists {
// Builds the hierarchy of the scene's non-degenerate triangles (hierarchy_builder.cpp) into impl's
// volumes and events, and its stats but build_seconds.
void build_hierarchy(SortedLists::Impl& impl);
}  // namespace lists

}  // namespace beamtrace
