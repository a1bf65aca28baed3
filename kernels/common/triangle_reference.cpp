#include "common/triangle_reference.hpp"

namespace beamtrace {

void watertight_edges_double(float ax, float ay, float bx, float by, float cx, float cy, float& u, float& v, float& w) {
    const double cxby = double(cx) * double(by), cybx = double(cy) * double(bx);
    const double axcy = double(ax) * double(cy), aycx = double(ay) * double(cx);
    const double bxay = double(bx) * double(ay), byax = double(by) * double(ax);
    u = float(cxby - cybx);
    v = float(axcy - aycx);
    w = float(bxay - byax);
}

bool intersect_triangle(const WatertightRay& r, const Triangle& tri, TriangleHit& hit) {
    const Float3 a = tri.v0 - r.org, b = tri.v1 - r.org, c = tri.v2 - r.org;
    const float az_ = a[r.kz], bz_ = b[r.kz], cz_ = c[r.kz];
    const float ax = a[r.kx] - r.sx * az_, ay = a[r.ky] - r.sy * az_;
    const float bx = b[r.kx] - r.sx * bz_, by = b[r.ky] - r.sy * bz_;
    const float cx = c[r.kx] - r.sx * cz_, cy = c[r.ky] - r.sy * cz_;
    float u = cx * by - cy * bx;
    float v = ax * cy - ay * cx;
    float w = bx * ay - by * ax;
    if (u == 0.0f || v == 0.0f || w == 0.0f) watertight_edges_double(ax, ay, bx, by, cx, cy, u, v, w);
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
    const float det = (u + v) + w;
    if (det == 0.0f) return false;
    const float t_scaled = (u * (r.sz * az_) + v * (r.sz * bz_)) + w * (r.sz * cz_);
    const float rcp = 1.0f / det;
    const float t = t_scaled * rcp;
    if (!(t >= r.tnear && t <= r.tfar && t < kInfinity)) return false;
    hit = TriangleHit{t, v * rcp, w * rcp};
    return true;
}

}  // namespace beamtrace
