#pragma once
// Build statistics of acceleration structures.
#include <cstddef>
#include <cstdint>

namespace beamtrace {

struct KdBuildStats {
    std::size_t triangles = 0;             // triangles in the scene
    std::size_t degenerate_triangles = 0;  // zero-area triangles, left out of the tree
    std::size_t nodes = 0;                 // inner nodes + leaves
    std::size_t inner_nodes = 0;
    std::size_t leaves = 0;
    std::size_t empty_leaves = 0;
    std::size_t flat_leaves = 0;           // leaves of zero extent along some axis
    int depth = 0;                         // deepest leaf (root = 0)
    std::size_t triangle_references = 0;   // sum over leaves of their triangle counts
    double mean_triangles_per_leaf = 0.0;  // over non-empty leaves
    std::size_t empty_cell_splits = 0;     // splits chosen by rule 1
    std::size_t flat_cell_splits = 0;      // splits chosen by rule 2
    std::size_t tiny_cell_leaves = 0;      // leaves made by rule 3
    std::size_t bytes = 0;                 // nodes + triangle references
    // The tree's SAH cost relative to its root's area: sum of traversal_cost x area over inner
    // nodes and intersection_cost x triangles x area over leaves, divided by the root's area.
    double sah_cost = 0.0;
    // Splits made in the binned upper levels (KdBuildRules::binned_above), rule 1's cuts there included.
    std::size_t binned_splits = 0;
    double build_seconds = 0.0;
};

}  // namespace beamtrace
