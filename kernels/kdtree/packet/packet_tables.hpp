#pragma once
// The tables packet traversal reads besides the tree, made once per tree on its first packet query
// (KdTree::Impl::packet_tables): each leaf's geometry box, the leaf triangles' corners as rows (what
// the frustum culling loads without gathering) and the packet kernels of the tree's instruction set.
#include <cstddef>
#include <vector>

#include "beamtrace/vec.hpp"
#include "kdtree/packet/packet_kernels.hpp"

namespace beamtrace::kdtree {

struct PacketTables {
    // Per node (boxes of inner nodes are empty): a leaf's triangles clipped to its cell, grown by a
    // relative slack; tighter than the cell, and where any hit that matters lies.
    std::vector<Box> geometry_boxes;
    // The corners of KdTree::Impl::leaf_triangles, nine padded rows (CornerRows).
    std::vector<float> corner_rows;
    std::size_t corner_stride = 0;
    // The absolute widening of packet intervals: the scene's scale (its diagonal or its largest
    // coordinate) times 2^-20.
    float pad = 0.0f;
    const PacketKernels* kernels = nullptr;

    CornerRows rows() const { return {corner_rows.data(), corner_stride}; }
    std::size_t bytes() const { return geometry_boxes.size() * sizeof(Box) + corner_rows.size() * sizeof(float); }
};

}  // namespace beamtrace::kdtree
