#pragma once
// TileRasteriser: the tiles of a PSF a triangle touches (section 3.2, Figure 1), conservatively.
//
// Each edge is walked through the tile rows it crosses; in every row the part of the edge inside
// that row's strip gives the columns it touches. That is the 8-connected walk of Figure 1: a tile
// the edge only clips at a corner is included, which a DDA would miss. The interior is then filled
// row by row between the leftmost and rightmost tile the edges reached (a triangle meets each row
// strip in a convex piece whose extreme points lie on its edges).
//
// Padding: the triangle is grown by `pad` in x and y (every strip is widened by pad above and below,
// every span by pad left and right), so a tile within pad of the triangle is included as well. Work
// is in double on the canonical corners; see canonical_frame.hpp for why pad makes this safe.
#include <algorithm>
#include <limits>
#include <vector>

#include "vlf/directions/canonical_frame.hpp"

namespace beamtrace::vlf {

class TileRasteriser {
public:
    explicit TileRasteriser(const TileGrid& grid) : grid_(grid), lo_(std::size_t(grid.n)), hi_(std::size_t(grid.n)) {}

    // Calls emit(column, row) once for every tile the padded triangle touches, row by row.
    template <class Emit>
    void rasterise(const Vec3d* v, Emit&& emit) {
        const TileGrid& g = grid_;
        const double pad = g.pad;
        const double ylo = std::min({v[0].y, v[1].y, v[2].y}), yhi = std::max({v[0].y, v[1].y, v[2].y});
        const int r0 = g.cell(ylo - pad), r1 = g.cell(yhi + pad);
        for (int r = r0; r <= r1; ++r) {
            lo_[std::size_t(r)] = std::numeric_limits<double>::infinity();
            hi_[std::size_t(r)] = -std::numeric_limits<double>::infinity();
        }
        for (int e = 0; e < 3; ++e) walk_edge(v[e], v[(e + 1) % 3]);
        for (int r = r0; r <= r1; ++r) {
            const double lo = lo_[std::size_t(r)], hi = hi_[std::size_t(r)];
            if (!(lo <= hi)) continue;
            const int c0 = g.cell(lo), c1 = g.cell(hi);
            for (int c = c0; c <= c1; ++c) emit(c, r);
        }
    }

    // Whether rasterise(v, ...) emits tile (c, r): the same arithmetic for that one row (lazy tile
    // builds decide triangle by triangle, and must decide as the whole-PSF build does).
    static bool touches(const TileGrid& g, const Vec3d* v, int c, int r) {
        const double pad = g.pad;
        const double ylo = std::min({v[0].y, v[1].y, v[2].y}), yhi = std::max({v[0].y, v[1].y, v[2].y});
        if (r < g.cell(ylo - pad) || r > g.cell(yhi + pad)) return false;
        double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
        for (int e = 0; e < 3; ++e) {
            const Vec3d& a = v[e];
            const Vec3d& b = v[(e + 1) % 3];
            if (r < g.cell(std::min(a.y, b.y) - pad) || r > g.cell(std::max(a.y, b.y) + pad)) continue;
            edge_in_row(g, a, b, r, lo, hi);
        }
        if (!(lo <= hi)) return false;
        return c >= g.cell(lo) && c <= g.cell(hi);
    }

private:
    // The 8-connected walk of one edge: for each row strip (widened by pad) the edge enters, the
    // x extent of the edge's part inside it, widened by pad, joins that row's span.
    void walk_edge(const Vec3d& a, const Vec3d& b) {
        const TileGrid& g = grid_;
        const double pad = g.pad;
        const int r0 = g.cell(std::min(a.y, b.y) - pad), r1 = g.cell(std::max(a.y, b.y) + pad);
        for (int r = r0; r <= r1; ++r) edge_in_row(g, a, b, r, lo_[std::size_t(r)], hi_[std::size_t(r)]);
    }

    // Row r of edge (a, b)'s walk (r among the rows the edge's padded extent covers): the x extent of
    // its part inside the row's padded strip, widened by pad, joins [lo, hi].
    static void edge_in_row(const TileGrid& g, const Vec3d& a, const Vec3d& b, int r, double& lo, double& hi) {
        const double pad = g.pad;
        const double dy = b.y - a.y, dx = b.x - a.x;
        double xa = a.x, xb = b.x;
        if (dy != 0.0) {
            const double s_lo = g.edge(r) - pad, s_hi = g.edge(r) + g.h + pad;
            double t0 = (s_lo - a.y) / dy, t1 = (s_hi - a.y) / dy;
            if (t0 > t1) std::swap(t0, t1);
            t0 = std::max(t0, 0.0);
            t1 = std::min(t1, 1.0);
            if (t0 > t1) return;
            xa = a.x + t0 * dx;
            xb = a.x + t1 * dx;
        }
        lo = std::min(lo, std::min(xa, xb) - pad);
        hi = std::max(hi, std::max(xa, xb) + pad);
    }

    TileGrid grid_;
    std::vector<double> lo_, hi_;  // per row: x extent of the padded triangle
};

}  // namespace beamtrace::vlf
