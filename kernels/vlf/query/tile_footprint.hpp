#pragma once
// Footprints inside one tile: the part of the tile's (padded) square that a triangle covers, or that
// a ray crosses over part of its segment, as a box on a 256 x 256 lattice over that square. A tile
// entry carries its triangle's footprint (the box of its part inside the padded prism, grown by the
// padding) in one 32-bit word; a ray skips the entries whose footprint misses its own, before any
// triangle test. This is not in the paper (see docs/vlf.md): the tile-BSP orders a tile's triangles
// along the beam only, and in dense tiles (thousands of triangles) a ray would test all those of
// its leaves although it crosses a small part of the tile.
//
// Packing: a triangle's box (x0, y0, x1, y1) is the word with bytes (x0, y0, 255 - x1, 255 - y1),
// low byte first; a ray's box is (x1, y1, 255 - x0, 255 - y0). The boxes overlap exactly when every
// byte of the triangle's word is <= the same byte of the ray's word: max(f, ray) == ray, bytewise,
// which SIMD checks for 4, 8 or 16 entries at once (footprint_scan_impl.hpp).
#include <cmath>
#include <cstdint>

#include "vlf/directions/canonical_frame.hpp"

namespace beamtrace::vlf {

// The lattice over one tile's padded square.
struct FootprintLattice {
    double x0 = 0, y0 = 0;  // lower corner of the padded square
    double scale = 0;       // lattice cells per unit of length

    static FootprintLattice of_tile(const TileGrid& g, int column, int row) {
        return FootprintLattice{g.edge(column) - g.pad, g.edge(row) - g.pad, g.lattice_scale};
    }
    // floor(q) clamped to [0, 255] (truncation is floor for the positive q that reach it).
    static std::uint32_t cell(double q) { return q < 1.0 ? 0u : (q >= 255.0 ? 255u : std::uint32_t(q)); }
    // Footprint word of a triangle whose part inside the padded prism spans [xlo, xhi] x [ylo, yhi].
    std::uint32_t triangle(double xlo, double xhi, double ylo, double yhi, double pad) const {
        const std::uint32_t a = cell((xlo - pad - x0) * scale), b = cell((ylo - pad - y0) * scale);
        const std::uint32_t c = cell((xhi + pad - x0) * scale), d = cell((yhi + pad - y0) * scale);
        return a | (b << 8) | ((255u - c) << 16) | ((255u - d) << 24);
    }
    // Footprint word of a ray crossing [xlo, xhi] x [ylo, yhi] of the tile.
    std::uint32_t ray(double xlo, double xhi, double ylo, double yhi) const {
        const std::uint32_t a = cell((xlo - x0) * scale), b = cell((ylo - y0) * scale);
        const std::uint32_t c = cell((xhi - x0) * scale), d = cell((yhi - y0) * scale);
        return c | (d << 8) | ((255u - a) << 16) | ((255u - b) << 24);
    }
};

// Whether a triangle's footprint meets a ray's.
inline bool footprints_meet(std::uint32_t triangle, std::uint32_t ray) {
    for (int shift = 0; shift < 32; shift += 8)
        if (((triangle >> shift) & 0xFFu) > ((ray >> shift) & 0xFFu)) return false;
    return true;
}

}  // namespace beamtrace::vlf
