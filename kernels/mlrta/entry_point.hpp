#pragma once
// Where the traversal of a group of rays starts: a node, its box, and whether the group certainly
// misses everything below it.
#include <cstdint>

#include "beamtrace/vec.hpp"

namespace beamtrace::mlrta {

struct EntryPoint {
    std::uint32_t node = 0;
    Box box;
    bool misses = false;  // no ray of the group can hit anything (EP search found no potential leaf)
};

}  // namespace beamtrace::mlrta
