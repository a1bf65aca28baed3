#pragma once
// A ray in the canonical space of its PSF, cut to the scene's box (section 5: "the ray is truncated
// to its intersections with the scene's boundary"): the segment [t0, t1] the tile walk follows,
// and the tile where it starts. t keeps the ray's own parameterisation (the rotation preserves
// lengths). The packet lookup (packet_lookup_impl.hpp) computes exactly the same, 16 rays at a
// time, with the same operations in the same order.
#include <cmath>

#include "beamtrace/ray.hpp"
#include "vlf/directions/canonical_frame.hpp"

namespace beamtrace::vlf {

struct CanonicalRay {
    double ox, oy, oz;              // origin
    double dx, dy, dz;              // direction
    double t0, t1;                  // the segment inside the box and inside [tnear, tfar]
    int column, row;                // tile of the point at t0
    double inv_dx, inv_dy, inv_dz;  // 1 / d (infinite for a zero component)
};

// The field's box grown by the padding, in double.
struct WorldBox {
    double lower[3], upper[3];
    static WorldBox around(const Box& b, double pad) {
        return WorldBox{{b.lower.x - pad, b.lower.y - pad, b.lower.z - pad},
                        {b.upper.x + pad, b.upper.y + pad, b.upper.z + pad}};
    }
};

// std::max / std::min as the SIMD code spells them (the first argument unless the second wins).
inline double max_of(double a, double b) { return a < b ? b : a; }
inline double min_of(double a, double b) { return b < a ? b : a; }

// [tnear, tfar] cut to the box; false if nothing is left (or the ray holds NaNs).
inline bool clip_to_world_box(const WorldBox& box, const Ray& ray, double& t0, double& t1) {
    t0 = ray.tnear;
    t1 = ray.tfar;
    for (int k = 0; k < 3; ++k) {
        const double o = ray.org[k], d = ray.dir[k];
        if (!(std::fabs(o) < HUGE_VAL)) return false;  // NaN or infinite origin
        if (d == 0.0) {
            if (!(o >= box.lower[k] && o <= box.upper[k])) return false;
            continue;
        }
        const double inv = 1.0 / d;
        const double ta = (box.lower[k] - o) * inv, tb = (box.upper[k] - o) * inv;
        t0 = max_of(t0, min_of(ta, tb));
        t1 = min_of(t1, max_of(ta, tb));
    }
    return t0 <= t1;
}

// False when the ray's segment misses the box.
inline bool make_canonical_ray(const CanonicalFrame& frame, const TileGrid& grid, const WorldBox& box, const Ray& ray,
                               CanonicalRay& out) {
    if (!clip_to_world_box(box, ray, out.t0, out.t1)) return false;
    const Vec3d o = frame.point(ray.org, grid), d = frame.rotate(to_double(ray.dir));
    out.ox = o.x;
    out.oy = o.y;
    out.oz = o.z;
    out.dx = d.x;
    out.dy = d.y;
    out.dz = d.z;
    out.column = grid.cell(o.x + out.t0 * d.x);
    out.row = grid.cell(o.y + out.t0 * d.y);
    out.inv_dx = 1.0 / d.x;
    out.inv_dy = 1.0 / d.y;
    out.inv_dz = 1.0 / d.z;
    return true;
}

}  // namespace beamtrace::vlf
