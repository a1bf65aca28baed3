#pragma once
// A ray in the canonical space of its PSF, cut to the scene's bounding sphere (section 5: "the ray
// is truncated to its intersections with the scene's boundary"): the segment [t0, t1] the tile walk
// follows. t keeps the ray's own parameterisation (the rotation preserves lengths).
#include <cmath>

#include "beamtrace/ray.hpp"
#include "vlf/canonical_frame.hpp"

namespace beamtrace::vlf {

struct CanonicalRay {
    double ox, oy, oz;  // origin
    double dx, dy, dz;  // direction
    double t0, t1;      // the segment inside the sphere and inside [tnear, tfar]
};

// False when the ray misses the sphere of radius clip_radius around the grid's centre, or its
// interval [tnear, tfar] lies outside it (or the ray holds NaNs).
inline bool make_canonical_ray(const CanonicalFrame& frame, const TileGrid& grid, double clip_radius, const Ray& ray,
                               CanonicalRay& out) {
    const Vec3d o = frame.point(ray.org, grid), d = frame.rotate(to_double(ray.dir));
    const double a = d.x * d.x + d.y * d.y + d.z * d.z;
    const double b = o.x * d.x + o.y * d.y + o.z * d.z;
    const double c = o.x * o.x + o.y * o.y + o.z * o.z - clip_radius * clip_radius;
    const double disc = b * b - a * c;
    if (!(disc >= 0.0) || !(a > 0.0)) return false;
    // Roots of a t^2 + 2 b t + c without cancellation.
    const double q = -(b + std::copysign(std::sqrt(disc), b));
    double ta, tb;
    if (q == 0.0) {
        ta = tb = 0.0;
    } else {
        ta = q / a;
        tb = c / q;
        if (ta > tb) std::swap(ta, tb);
    }
    out.t0 = std::max(ta, double(ray.tnear));
    out.t1 = std::min(tb, double(ray.tfar));
    if (!(out.t0 <= out.t1)) return false;
    out.ox = o.x; out.oy = o.y; out.oz = o.z;
    out.dx = d.x; out.dy = d.y; out.dz = d.z;
    return true;
}

}  // namespace beamtrace::vlf
