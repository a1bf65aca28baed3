#pragma once
// The canonical space of a PSF (section 3.1) and the tile grid shared by every PSF of a field.
//
// Canonical space: the scene's bounding sphere moved to the origin and rotated so that the PSF's
// direction omega becomes +z: p' = M (p - centre), with M's rows an orthonormal frame (e1, e2, omega).
// The tiles are the n x n squares of side h = 2 R / n covering [-R, R]^2 in canonical (x, y), R the
// sphere's radius: the base of the paper's cuboid, sized to the sphere so that every rotation of the
// scene fits.
//
// Floating point never drops a triangle: everything geometric is computed in double, and triangles
// are padded by `pad` (4e-5 R) both across the beam (rasterisation, clipping to the tile prism) and
// along it (the tile-BSP's depth ranges). The padding dwarfs double rounding; it is there for the
// float watertight test, whose hit point may lie a few float ulps of the ray's length off the
// triangle (see docs/vlf.md).
#include <algorithm>
#include <cmath>

#include "beamtrace/vec.hpp"

namespace beamtrace::vlf {

inline constexpr double kPadFraction = 4e-5;  // padding, as a fraction of R

struct Vec3d {
    double x = 0, y = 0, z = 0;
};

inline Vec3d to_double(Float3 f) { return {f.x, f.y, f.z}; }

// The grid: the same for every PSF of a field.
struct TileGrid {
    Vec3d centre;
    double radius = 1.0;  // R: every triangle lies within this distance of centre
    int n = 128;          // tiles per side
    double h = 0.0;       // tile side, 2 R / n
    double inv_h = 0.0;
    double pad = 0.0;            // padding of triangles (across and along the beam)
    double lattice_scale = 0.0;  // footprint lattice cells per unit of length (tile_footprint.hpp)

    static TileGrid around(const Box& box, int n) {
        TileGrid g;
        g.centre = {0.5 * (double(box.lower.x) + box.upper.x), 0.5 * (double(box.lower.y) + box.upper.y),
                    0.5 * (double(box.lower.z) + box.upper.z)};
        const double ex = double(box.upper.x) - box.lower.x, ey = double(box.upper.y) - box.lower.y,
                     ez = double(box.upper.z) - box.lower.z;
        double r = 0.5 * std::sqrt(ex * ex + ey * ey + ez * ez);
        // A scene of one point: any positive radius; otherwise a hair more than half the diagonal.
        r = r > 0.0 ? r * (1.0 + 1e-9) : 1.0;
        g.radius = r;
        g.n = n;
        g.h = 2.0 * r / n;
        g.inv_h = 1.0 / g.h;
        g.pad = kPadFraction * r;
        g.lattice_scale = 256.0 / (g.h + 2.0 * g.pad);
        return g;
    }
    // Lower corner of the grid in canonical x and y.
    double origin() const { return -radius; }
    // Tile column (or row) of a canonical coordinate, clamped into the grid.
    int cell(double c) const {
        const double f = std::floor((c + radius) * inv_h);
        return f < 0.0 ? 0 : (f >= n ? n - 1 : int(f));
    }
    // Lower edge of tile column (or row) i.
    double edge(int i) const { return -radius + i * h; }
};

// The rotation of one PSF: rows e1, e2, e3 = omega.
struct CanonicalFrame {
    Vec3d e1, e2, e3;

    static CanonicalFrame towards(Float3 omega) {
        CanonicalFrame f;
        const Vec3d w = to_double(omega);
        const double wl = std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
        f.e3 = {w.x / wl, w.y / wl, w.z / wl};
        // e1: perpendicular to omega, from the world axis least aligned with it.
        const Vec3d a = std::fabs(f.e3.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
        Vec3d c{a.y * f.e3.z - a.z * f.e3.y, a.z * f.e3.x - a.x * f.e3.z, a.x * f.e3.y - a.y * f.e3.x};
        const double cl = std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
        f.e1 = {c.x / cl, c.y / cl, c.z / cl};
        f.e2 = {f.e3.y * f.e1.z - f.e3.z * f.e1.y, f.e3.z * f.e1.x - f.e3.x * f.e1.z,
                f.e3.x * f.e1.y - f.e3.y * f.e1.x};
        return f;
    }
    // A direction (no translation).
    Vec3d rotate(Vec3d d) const {
        return {e1.x * d.x + e1.y * d.y + e1.z * d.z, e2.x * d.x + e2.y * d.y + e2.z * d.z,
                e3.x * d.x + e3.y * d.y + e3.z * d.z};
    }
    // A point, relative to the grid's centre.
    Vec3d point(Float3 p, const TileGrid& g) const {
        return rotate(Vec3d{double(p.x) - g.centre.x, double(p.y) - g.centre.y, double(p.z) - g.centre.z});
    }
};

}  // namespace beamtrace::vlf
