#pragma once
// Where the traversal of a group of rays starts: a node, its box, and whether the group certainly
// misses everything below it.
#include <cstdint>

#include "beamtrace/ray.hpp"
#include "beamtrace/vec.hpp"

namespace beamtrace::mlrta {

struct EntryPoint {
    std::uint32_t node = 0;
    Box box;
    bool misses = false;  // no ray of the group can hit anything (EP search found no potential leaf)
    // A triangle every ray of the group hits within its segment (kNoHit if none is known): then
    // every ray is occluded, and nothing beyond that triangle matters to a closest hit.
    std::uint32_t blocker = kNoHit;
    bool blocked() const { return blocker != kNoHit; }
};

}  // namespace beamtrace::mlrta
