#pragma once
// A node of the ray-space hierarchy: a sphere holding where its rays' segments start (the bounding
// points, ray_keys.hpp) and a cone holding their directions; and the sphere-cone test (CRSH eq. 9 in
// the complete conservative form of the notes), which keeps a bounding sphere that some ray of the
// node may reach.
#include <cstdint>
#include <limits>

#include "crsh/cone.hpp"
#include "crsh/vec3d.hpp"

namespace beamtrace::crsh {

struct RayNode {
    Vec3d centre;
    double radius = 0.0;
    Cone cone;
    // What the test reads of the cone, from the spread padded by kSpreadPad: cos and sin, and wide
    // (spread >= pi/2: accept everything).
    double cos_spread = 1.0, sin_spread = 0.0;
    bool wide = false;
    double rounding = 0.0;  // absolute slack for the double arithmetic about a far-off centre
    // The longest distance a ray of the node runs from its start (CrshSettings::segment_bound);
    // infinite: no bound (the paper's half-infinite rays).
    double length = std::numeric_limits<double>::infinity();
    // Level 1: rays first .. first + count - 1 of the sorted order. Above: those children of the level below.
    std::uint32_t first = 0, count = 0;
};

inline constexpr double kSpreadPad = 1e-12;

// Fills the test's fields from centre, radius and cone.
inline void finish_node(RayNode& n) {
    const double spread = n.cone.spread + kSpreadPad;
    n.wide = spread >= kHalfPi;
    n.cos_spread = n.wide ? 0.0 : std::cos(spread);
    n.sin_spread = n.wide ? 1.0 : std::sin(spread);
    n.rounding = 1e-14 * norm1(n.centre);
}

// Whether a sphere (centre p, radius r) may meet a ray of the node. The rays start inside the
// node's sphere (C, d) and run along directions inside its cone (axis a, half-angle alpha), so every
// point they reach lies within d of the cone K of apex C: keep iff the distance from p to K is at
// most R = d + r. With v = p - C, s = v.a and rho = |v x a| (the distance from the axis):
//   alpha >= 90 degrees                       keep;
//   s cos(alpha) + rho sin(alpha) < 0         the apex is K's nearest point: keep iff |v| <= R;
//   otherwise                                 keep iff rho cos(alpha) - s sin(alpha) <= R
// (p inside K makes the left side negative). Computed in double with squares instead of roots, and a
// margin far above double rounding (1e-9 relative), so that nothing a ray can reach is culled.
// With a finite length L (segment bound), first: keep only if |v| <= R + L, for any cone.
inline bool sphere_meets_node(const RayNode& n, double px, double py, double pz, double r) {
    const double vx = px - n.centre.x, vy = py - n.centre.y, vz = pz - n.centre.z;
    if (n.length < std::numeric_limits<double>::infinity()) {
        const double far = n.radius + r + n.length;
        const double m = far * (1.0 + 1e-9) + n.rounding + 1e-14 * (std::fabs(px) + std::fabs(py) + std::fabs(pz));
        if (vx * vx + vy * vy + vz * vz > m * m) return false;
    }
    if (n.wide) return true;
    const Vec3d& a = n.cone.axis;
    const double s = vx * a.x + vy * a.y + vz * a.z;
    const double wx = vy * a.z - vz * a.y, wy = vz * a.x - vx * a.z, wz = vx * a.y - vy * a.x;
    const double rho2 = wx * wx + wy * wy + wz * wz;
    const double reach = n.radius + r;
    const double margin = 1e-9 * (std::fabs(vx) + std::fabs(vy) + std::fabs(vz) + reach) + n.rounding +
                          1e-14 * (std::fabs(px) + std::fabs(py) + std::fabs(pz));
    const double R = reach + margin;
    const double c = n.cos_spread, sn = n.sin_spread;
    // s cos + rho sin < 0, without the root: s < 0 and rho^2 sin^2 < s^2 cos^2.
    if (s < 0.0 && rho2 * (sn * sn) < s * s * (c * c)) return vx * vx + vy * vy + vz * vz <= R * R;
    const double right = R + s * sn;  // keep iff rho cos(alpha) <= R + s sin(alpha)
    if (right < 0.0) return false;
    return rho2 * (c * c) <= right * right;
}

}  // namespace beamtrace::crsh
