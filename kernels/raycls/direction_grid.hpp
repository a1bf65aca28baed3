#pragma once
// A light buffer's tile: a uniform grid of n x n direction cells over the part of the tile's (u, v)
// rectangle its candidates cover,
// each holding the tile's candidates whose direction rectangles meet it (padded by 1/64 of a cell,
// far above the rounding of the index arithmetic), in the tile list's order (key, then id), side by
// side in one array (offsets per cell). One pass over the tile's list makes every cell: the deeper
// levels of Arvo and Kirk's subdivision, made at once instead of level by level (docs/raycls.md).
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "raycls/candidate_list.hpp"

namespace beamtrace::raycls {

struct DirectionGrid {
    int n = 1;
    float u0 = -1, v0 = -1, cells_per_u = 0.5f, cells_per_v = 0.5f;
    std::vector<std::uint32_t> offsets;  // n * n + 1
    std::vector<Candidate> items;

    int index(float u, float v) const {
        const int i = std::clamp(int((u - u0) * cells_per_u), 0, n - 1);
        const int j = std::clamp(int((v - v0) * cells_per_v), 0, n - 1);
        return j * n + i;
    }
    std::span<const Candidate> cell(float u, float v) const {
        const int c = index(u, v);
        return {items.data() + offsets[std::size_t(c)], items.data() + offsets[std::size_t(c) + 1]};
    }
    std::size_t memory_bytes() const {
        return sizeof(DirectionGrid) + offsets.capacity() * sizeof(std::uint32_t) + items.capacity() * sizeof(Candidate);
    }
};

// The grid of a tile with bounds `cell` over its candidates (rect_items, sorted), n = 2^levels cells
// a side. The corners are copied from the scene.
DirectionGrid make_direction_grid(const CandidateList& tile, const CellBounds& cell, int levels, const Scene& scene);

}  // namespace beamtrace::raycls
