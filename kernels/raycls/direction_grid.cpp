// A light buffer tile's grid of direction cells (direction_grid.hpp).
#include "raycls/direction_grid.hpp"

#include <cmath>

namespace beamtrace::raycls {

namespace {

constexpr float kPad = 1.0f / 64.0f;  // of a cell

// The cells [first, last] a rectangle [lo, hi] covers on one axis.
inline void cover(float lo, float hi, float origin, float per, int n, int& first, int& last) {
    first = std::clamp(int(std::floor((lo - origin) * per - kPad)), 0, n - 1);
    last = std::clamp(int(std::floor((hi - origin) * per + kPad)), 0, n - 1);
}

}  // namespace

DirectionGrid make_direction_grid(const CandidateList& tile, const CellBounds& cell, int levels, const Scene& scene) {
    DirectionGrid g;
    g.n = 1 << levels;
    // Over the part of the tile the candidates' rectangles cover (a ray outside it can hit nothing,
    // so the clamped index giving it an edge cell costs tests, never an answer).
    float u0 = cell.u1, u1 = cell.u0, v0 = cell.v1, v1 = cell.v0;
    for (const RectCandidate& c : tile.rect_items) {
        u0 = std::min(u0, c.rect.u0);
        u1 = std::max(u1, c.rect.u1);
        v0 = std::min(v0, c.rect.v0);
        v1 = std::max(v1, c.rect.v1);
    }
    u0 = std::max(u0, cell.u0);
    u1 = std::min(u1, cell.u1);
    v0 = std::max(v0, cell.v0);
    v1 = std::min(v1, cell.v1);
    const float least_u = (cell.u1 - cell.u0) * (1.0f / 1048576.0f), least_v = (cell.v1 - cell.v0) * (1.0f / 1048576.0f);
    if (!(u1 - u0 > least_u)) u0 = cell.u0, u1 = cell.u1;
    if (!(v1 - v0 > least_v)) v0 = cell.v0, v1 = cell.v1;
    g.u0 = u0;
    g.v0 = v0;
    g.cells_per_u = float(g.n) / (u1 - u0);
    g.cells_per_v = float(g.n) / (v1 - v0);
    const std::size_t cells = std::size_t(g.n) * std::size_t(g.n);
    g.offsets.assign(cells + 1, 0);
    // Count, then place (in list order, so every cell stays sorted by key and id).
    for (const RectCandidate& c : tile.rect_items) {
        int i0, i1, j0, j1;
        cover(c.rect.u0, c.rect.u1, g.u0, g.cells_per_u, g.n, i0, i1);
        cover(c.rect.v0, c.rect.v1, g.v0, g.cells_per_v, g.n, j0, j1);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) ++g.offsets[std::size_t(j * g.n + i) + 1];
    }
    for (std::size_t k = 0; k < cells; ++k) g.offsets[k + 1] += g.offsets[k];
    g.items.resize(g.offsets[cells]);
    std::vector<std::uint32_t> at(g.offsets.begin(), g.offsets.end() - 1);
    for (const RectCandidate& c : tile.rect_items) {
        int i0, i1, j0, j1;
        cover(c.rect.u0, c.rect.u1, g.u0, g.cells_per_u, g.n, i0, i1);
        cover(c.rect.v0, c.rect.v1, g.v0, g.cells_per_v, g.n, j0, j1);
        const Candidate item{scene.triangle(c.id), c.key, c.id};
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) g.items[at[std::size_t(j * g.n + i)]++] = item;
    }
    return g;
}

}  // namespace beamtrace::raycls
