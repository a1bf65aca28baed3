#pragma once
// The tables packet traversal reads besides the tree, made once per tree on its first packet query
// (KdTree::Impl::packet_tables): each leaf's geometry box and the packet kernels of the tree's
// instruction set.
#include <cstddef>
#include <vector>

#include "beamtrace/vec.hpp"
#include "kdtree/packet/packet_kernels.hpp"

namespace beamtrace::kdtree {

struct PacketTables {
    // Per node (boxes of inner nodes are empty): a leaf's triangles clipped to its cell, grown by a
    // relative slack; tighter than the cell, and where any hit that matters lies.
    std::vector<Box> geometry_boxes;
    const PacketKernels* kernels = nullptr;

    std::size_t bytes() const { return geometry_boxes.size() * sizeof(Box); }
};

}  // namespace beamtrace::kdtree
