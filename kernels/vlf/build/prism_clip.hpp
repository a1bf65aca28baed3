#pragma once
// Clipping a triangle to a tile's prism (section 5: "polygons are clipped to the tile's boundary
// before comparing the polygon's depth range with the splitting planes"), in canonical space.
#include <algorithm>

#include "vlf/directions/canonical_frame.hpp"

namespace beamtrace::vlf {

// The prism over [x0, x1] x [y0, y1], infinite along z.
struct Prism {
    double x0, x1, y0, y1;
};

// The box of a triangle's part inside a prism.
struct ClippedBox {
    double xlo, xhi, ylo, yhi, zlo, zhi;
};

// Box (canonical x, y and depth z) of the part of triangle v inside the prism (boundary included);
// false if the triangle misses it. Sutherland-Hodgman against the four side planes, in double.
inline bool clip_to_prism(const Vec3d* v, const Prism& p, ClippedBox& out) {
    const double bx0 = std::min({v[0].x, v[1].x, v[2].x}), bx1 = std::max({v[0].x, v[1].x, v[2].x});
    const double by0 = std::min({v[0].y, v[1].y, v[2].y}), by1 = std::max({v[0].y, v[1].y, v[2].y});
    if (bx1 < p.x0 || bx0 > p.x1 || by1 < p.y0 || by0 > p.y1) return false;
    if (bx0 >= p.x0 && bx1 <= p.x1 && by0 >= p.y0 && by1 <= p.y1) {  // wholly inside: nothing to cut
        out = ClippedBox{bx0, bx1, by0, by1, std::min({v[0].z, v[1].z, v[2].z}), std::max({v[0].z, v[1].z, v[2].z})};
        return true;
    }
    // Sutherland-Hodgman against the side planes the triangle crosses (a convex polygon gains at
    // most one corner per plane: 3 + 4).
    Vec3d buf[2][8];
    int n = 3;
    for (int k = 0; k < 3; ++k) buf[0][k] = v[k];
    int cur = 0;
    const bool cross[4] = {bx0<p.x0, bx1> p.x1, by0<p.y0, by1> p.y1};
    for (int plane = 0; plane < 4; ++plane) {
        if (!cross[plane]) continue;
        // Plane `plane` keeps points with sign * (coordinate - bound) <= 0.
        const bool on_x = plane < 2;
        const double sign = (plane & 1) ? 1.0 : -1.0;
        const double bound = plane == 0 ? p.x0 : plane == 1 ? p.x1 : plane == 2 ? p.y0 : p.y1;
        const Vec3d* in = buf[cur];
        Vec3d* out = buf[cur ^ 1];
        int m = 0;
        double da = sign * ((on_x ? in[0].x : in[0].y) - bound);
        for (int k = 0; k < n; ++k) {
            const Vec3d& a = in[k];
            const Vec3d& b = in[k + 1 == n ? 0 : k + 1];
            const double db = sign * ((on_x ? b.x : b.y) - bound);
            if (da <= 0.0) out[m++] = a;
            if ((da <= 0.0) != (db <= 0.0)) {
                const double s = da / (da - db);
                out[m++] = Vec3d{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z)};
            }
            da = db;
        }
        n = m;
        cur ^= 1;
        if (n == 0) return false;
    }
    const Vec3d& q0 = buf[cur][0];
    out = ClippedBox{q0.x, q0.x, q0.y, q0.y, q0.z, q0.z};
    for (int k = 1; k < n; ++k) {
        const Vec3d& q = buf[cur][k];
        out.xlo = std::min(out.xlo, q.x);
        out.xhi = std::max(out.xhi, q.x);
        out.ylo = std::min(out.ylo, q.y);
        out.yhi = std::max(out.yhi, q.y);
        out.zlo = std::min(out.zlo, q.z);
        out.zhi = std::max(out.zhi, q.z);
    }
    return true;
}

}  // namespace beamtrace::vlf
