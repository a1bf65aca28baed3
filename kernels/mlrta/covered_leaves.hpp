#pragma once
// Per-node tables MLRTA computes once from the tree: subtree sizes (the paper's measure of geometric
// complexity below an entry point) and flat leaves completely covered by their triangles (which end
// every ray that crosses them: an entry-point search may stop there).
#include <cstdint>
#include <vector>

#include "kdtree/kd_node.hpp"

namespace beamtrace::mlrta {

std::vector<std::uint32_t> subtree_sizes(const KdTree::Impl& tree);

// A leaf is covered when it is flat (zero extent along one axis), its triangles lying in that plane
// do not overlap one another (2D separating-axis test in double precision) and their areas inside
// the leaf's face add up to the face's area (to 1e-9). Leaves with more than 64 triangles are not
// examined.
std::vector<std::uint8_t> covered_flat_leaves(const KdTree::Impl& tree);

}  // namespace beamtrace::mlrta
