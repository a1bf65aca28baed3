#pragma once
// Where the traversal of a group of rays starts: a node, its box, and whether the group certainly
// misses everything below it.
#include <cstdint>

#include "beamtrace/ray.hpp"
#include "beamtrace/vec.hpp"
#include "kdtree/packet/packet_traversal.hpp"

namespace beamtrace::mlrta {

using kdtree::Bifurcation;
using kdtree::NodeBox;

struct EntryPoint {
    std::uint32_t node = 0;
    Box box;
    bool misses = false;  // no ray of the group can hit anything (EP search found no potential leaf)
    // A triangle every ray of the group hits within its segment (kNoHit if none is known): then
    // every ray is occluded, and nothing beyond that triangle matters to a closest hit.
    std::uint32_t blocker = kNoHit;
    bool blocked() const { return blocker != kNoHit; }
};

// N objects of type T, not initialised: written before they are read (a stack).
template <class T, int N>
struct Uninitialised {
    Uninitialised() {}
    union {
        T at[N];
    };
};

// A node of the bifurcation stack is a kdtree::Bifurcation: both its children may be entered,
// `other` is not searched yet.

// Where an entry-point search found its first leaf with potential intersections, seen from the
// entry point it returned: that leaf and the bifurcations on its path below the entry point (the
// entry point first). Every leaf before it in the depth-first order holds nothing for the beam,
// hence nothing for any part of the beam, so a search for a part (a sub-tile) can start here
// instead of walking that empty part of the tree again (not in the paper; docs/mlrta.md). When the
// entry point is a bifurcation, the same holds for the walk of its other subtree: the first
// potential leaf found there and the nodes that walk had still to visit.
struct SearchTrail {
    static constexpr int kCapacity = 64;
    bool valid = false;
    int sign[3] = {0, 0, 0};  // the beam's direction signs: the depth-first order is theirs
    NodeBox first{};
    int count = 0;
    Uninitialised<Bifurcation, kCapacity> bif;
    bool second_valid = false;  // the walk of the entry point's other subtree (bif.at[0].other)
    NodeBox second{};
    int pending = 0;
    Uninitialised<NodeBox, kCapacity> rest;  // depth-first stack of that walk: the next on top
};

}  // namespace beamtrace::mlrta
