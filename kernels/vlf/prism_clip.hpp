#pragma once
// Clipping a triangle to a tile's prism (section 5: "polygons are clipped to the tile's boundary
// before comparing the polygon's depth range with the splitting planes"), in canonical space.
#include <algorithm>

#include "vlf/canonical_frame.hpp"

namespace beamtrace::vlf {

// The prism over [x0, x1] x [y0, y1], infinite along z.
struct Prism {
    double x0, x1, y0, y1;
};

// Depth range (canonical z) of the part of triangle v inside the prism (boundary included);
// false if the triangle misses it. Sutherland-Hodgman against the four side planes, in double.
inline bool clip_to_prism(const Vec3d* v, const Prism& p, double& zlo, double& zhi) {
    const double bx0 = std::min({v[0].x, v[1].x, v[2].x}), bx1 = std::max({v[0].x, v[1].x, v[2].x});
    const double by0 = std::min({v[0].y, v[1].y, v[2].y}), by1 = std::max({v[0].y, v[1].y, v[2].y});
    if (bx1 < p.x0 || bx0 > p.x1 || by1 < p.y0 || by0 > p.y1) return false;
    if (bx0 >= p.x0 && bx1 <= p.x1 && by0 >= p.y0 && by1 <= p.y1) {  // wholly inside: nothing to cut
        zlo = std::min({v[0].z, v[1].z, v[2].z});
        zhi = std::max({v[0].z, v[1].z, v[2].z});
        return true;
    }
    // A convex polygon gains at most one corner per plane: 3 + 4.
    Vec3d buf[2][8];
    int n = 3;
    for (int k = 0; k < 3; ++k) buf[0][k] = v[k];
    int cur = 0;
    // Plane k keeps points with s * coordinate <= s * bound: (axis, sign, bound).
    const struct { int axis; double sign, bound; } planes[4] = {
        {0, -1.0, p.x0}, {0, 1.0, p.x1}, {1, -1.0, p.y0}, {1, 1.0, p.y1}};
    for (const auto& pl : planes) {
        const Vec3d* in = buf[cur];
        Vec3d* out = buf[cur ^ 1];
        int m = 0;
        auto dist = [&](const Vec3d& q) { return pl.sign * ((pl.axis == 0 ? q.x : q.y) - pl.bound); };  // <= 0 inside
        for (int k = 0; k < n; ++k) {
            const Vec3d& a = in[k];
            const Vec3d& b = in[(k + 1) % n];
            const double da = dist(a), db = dist(b);
            if (da <= 0.0) out[m++] = a;
            if ((da <= 0.0) != (db <= 0.0)) {
                const double s = da / (da - db);
                out[m++] = Vec3d{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z)};
            }
        }
        n = m;
        cur ^= 1;
        if (n == 0) return false;
    }
    zlo = zhi = buf[cur][0].z;
    for (int k = 1; k < n; ++k) {
        zlo = std::min(zlo, buf[cur][k].z);
        zhi = std::max(zhi, buf[cur][k].z);
    }
    return true;
}

}  // namespace beamtrace::vlf
