#pragma once
// The candidate set of a ray-space cell: the triangles its beam may meet, sorted by where they start
// along the face's direction (key = s * the triangle's nearest coordinate on the face axis: the
// smallest x_k for + faces, minus the largest for - faces), ties by triangle id, with copies of their
// corners side by side so a ray's tests read them front to back.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "beamtrace/scene.hpp"
#include "kdtree/kd_node.hpp"
#include "raycls/cell_beam.hpp"

namespace beamtrace::raycls {

// The rectangle of directions (u, v on the face) from a light buffer's apex box to a triangle.
struct DirectionRect {
    float u0, u1, v0, v1;
};

// One candidate: 44 bytes, read front to back by a ray's tests.
struct Candidate {
    Triangle corners;
    float key;
    std::uint32_t id;
};

// A light buffer's candidate before its cell is final: what the filtering reads (24 bytes).
struct RectCandidate {
    DirectionRect rect;  // seen from the apex box
    float key;
    std::uint32_t id;
};

// Cells of the 5D tree hold items; a light buffer's tile holds rect_items until its grid is made
// (direction_grid.hpp).
struct CandidateList {
    std::vector<Candidate> items;
    std::vector<RectCandidate> rect_items;

    std::size_t size() const { return items.size() + rect_items.size(); }
    std::size_t memory_bytes() const {
        return items.capacity() * sizeof(Candidate) + rect_items.capacity() * sizeof(RectCandidate);
    }
};

// The key of a triangle on a face.
float candidate_key(const Triangle& tri, int face);

// The non-degenerate triangles of the kd-tree's leaves that the beam may meet (the tree's nodes
// culled by the beam first; each triangle once, however many leaves hold it).
CandidateList candidates_from_tree(const KdTree::Impl& tree, const CellBeam& beam, int face);

// The parent's candidates the beam may meet, in the parent's order (the same face).
CandidateList candidates_from_parent(const CandidateList& parent, const CellBeam& beam);

// Light buffers: the items (made by candidates_from_tree) become rect_items, with the directions from
// the apex box to each triangle. A triangle not wholly in front of the box gets the whole face (it
// cannot be bounded; only triangles next to the light are). direction_margin pads every rectangle.
void add_direction_rects(CandidateList& list, const Box& apex, int face, double direction_margin);

}  // namespace beamtrace::raycls
