// Double-precision distances between ray segments and triangle edges, and between the ends of ray
// segments and the points where their lines cross triangles.
#include "oracle/ray_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace beamtrace::oracle {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Double3 operator-(Double3 a, Double3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Double3 operator+(Double3 a, Double3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Double3 operator*(Double3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(Double3 a, Double3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double norm(Double3 a) { return std::sqrt(dot(a, a)); }
Double3 cross(Double3 a, Double3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

// Distance from point p to segment [q0, q1].
double point_segment_distance(Double3 p, Double3 q0, Double3 q1) {
    const Double3 d = q1 - q0;
    const double len2 = dot(d, d);
    const double t = len2 > 0.0 ? clamp01(dot(p - q0, d) / len2) : 0.0;
    return norm(p - (q0 + d * t));
}

}  // namespace

double segment_distance(Double3 p0, Double3 p1, Double3 q0, Double3 q1) {
    // The minimum is either at an endpoint of one segment (always the case for parallel segments
    // and for points) or at the interior critical point of the two parametric lines. Taking the
    // endpoint distances as well keeps the result right when the critical point is ill-conditioned
    // (nearly parallel segments): a poorly placed interior candidate can only be too far, never
    // too near, because it is the distance between two actual points of the segments.
    double best = std::min({point_segment_distance(p0, q0, q1), point_segment_distance(p1, q0, q1),
                            point_segment_distance(q0, p0, p1), point_segment_distance(q1, p0, p1)});
    const Double3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const double a = dot(d1, d1), e = dot(d2, d2), b = dot(d1, d2);
    const double denom = a * e - b * b;  // |d1 x d2|^2 >= 0
    if (a > 0.0 && e > 0.0 && denom > 0.0) {
        const double c = dot(d1, r), f = dot(d2, r);
        const double s = (b * f - c * e) / denom;
        const double t = (a * f - b * c) / denom;
        if (s >= 0.0 && s <= 1.0 && t >= 0.0 && t <= 1.0) best = std::min(best, norm((p0 + d1 * s) - (q0 + d2 * t)));
    }
    return best;
}

RaySegment clip_to_scene(const Scene& scene, const Ray& ray) {
    RaySegment seg;
    const Double3 org = to_double(ray.org), dir = to_double(ray.dir);
    const double len = norm(dir);
    if (!(len > 0.0) || !std::isfinite(len)) return seg;
    const Box& box = scene.bounds();
    const double diag = box.diagonal();
    const double t_exit = (norm(org - to_double(box.center())) + diag) / len;
    const double t0 = ray.tnear;
    const double t1 = std::min<double>(ray.tfar, t_exit);
    if (std::isnan(t0) || std::isnan(t1) || !std::isfinite(t0) || !(t0 <= t1)) return seg;
    seg.a = org + dir * t0;
    seg.b = org + dir * t1;
    seg.empty = false;
    return seg;
}

double edge_distance(const Triangle& tri, const RaySegment& segment) {
    if (segment.empty) return kInf;
    const Double3 v0 = to_double(tri.v0), v1 = to_double(tri.v1), v2 = to_double(tri.v2);
    return std::min({segment_distance(segment.a, segment.b, v0, v1), segment_distance(segment.a, segment.b, v1, v2),
                     segment_distance(segment.a, segment.b, v2, v0)});
}

namespace {

// Where the ray's line (any t) crosses the triangle, in double (Moeller-Trumbore without a range of
// t); false when it misses, runs parallel to the plane, or the ray is not finite.
bool line_crossing(const Triangle& tri, const Ray& ray, double& t) {
    const Double3 org = to_double(ray.org), dir = to_double(ray.dir);
    if (!std::isfinite(norm(dir)) || !std::isfinite(norm(org))) return false;
    const Double3 v0 = to_double(tri.v0), e1 = to_double(tri.v1) - v0, e2 = to_double(tri.v2) - v0;
    const Double3 p = cross(dir, e2);
    const double det = dot(e1, p);
    if (det == 0.0 || !std::isfinite(det)) return false;
    const Double3 s = org - v0, q = cross(s, e1);
    const double u = dot(s, p) / det, v = dot(dir, q) / det;
    if (!(u >= 0.0 && v >= 0.0 && u + v <= 1.0)) return false;
    t = dot(e2, q) / det;
    return std::isfinite(t);
}

}  // namespace

double end_distance(const Triangle& tri, const Ray& ray) {
    const double len = norm(to_double(ray.dir));
    double t = 0.0;
    if (!(len > 0.0) || !line_crossing(tri, ray, t)) return kInf;
    double best = kInf;
    for (const double end : {double(ray.tnear), double(ray.tfar)})
        if (std::isfinite(end)) best = std::min(best, std::fabs(t - end) * len);
    return best;
}

double grazing_distance(const Scene& scene) { return 1e-5 * double(scene.bounds().diagonal()); }

bool near_edge_of_any(const Scene& scene, const RaySegment& segment, double distance) {
    if (segment.empty) return false;
    // The segment's box grown by `distance`: a triangle whose box misses it has no edge within reach.
    const double lo[3] = {std::min(segment.a.x, segment.b.x) - distance, std::min(segment.a.y, segment.b.y) - distance,
                          std::min(segment.a.z, segment.b.z) - distance};
    const double hi[3] = {std::max(segment.a.x, segment.b.x) + distance, std::max(segment.a.y, segment.b.y) + distance,
                          std::max(segment.a.z, segment.b.z) + distance};
    const auto n = static_cast<std::uint32_t>(scene.triangle_count());
    for (std::uint32_t id = 0; id < n; ++id) {
        if (scene.is_degenerate(id)) continue;
        const Triangle& t = scene.triangle(id);
        bool outside = false;
        for (int axis = 0; axis < 3 && !outside; ++axis) {
            const double tmin = std::min({t.v0[axis], t.v1[axis], t.v2[axis]});
            const double tmax = std::max({t.v0[axis], t.v1[axis], t.v2[axis]});
            outside = tmax < lo[axis] || tmin > hi[axis];
        }
        if (!outside && edge_distance(t, segment) <= distance) return true;
    }
    return false;
}

EndCrossings end_crossings(const Scene& scene, const Ray& ray, double distance) {
    EndCrossings out;
    const double len = norm(to_double(ray.dir));
    if (!(len > 0.0) || !std::isfinite(len) || std::isnan(ray.tnear) || std::isnan(ray.tfar) || ray.tnear > ray.tfar)
        return out;
    const double w = distance / len;  // the distance as a range of t
    const auto n = static_cast<std::uint32_t>(scene.triangle_count());
    // Whether triangle t's box meets the box [lo, hi].
    auto meets = [](const Triangle& t, const double* lo, const double* hi) {
        for (int axis = 0; axis < 3; ++axis) {
            if (std::max({t.v0[axis], t.v1[axis], t.v2[axis]}) < lo[axis]) return false;
            if (std::min({t.v0[axis], t.v1[axis], t.v2[axis]}) > hi[axis]) return false;
        }
        return true;
    };
    // First the ends: only triangles whose box lies within reach of an end point can cross there.
    const Double3 org = to_double(ray.org), dir = to_double(ray.dir);
    for (const double end : {double(ray.tnear), double(ray.tfar)}) {
        if (!std::isfinite(end)) continue;
        const Double3 p = org + dir * end;
        const double lo[3] = {p.x - distance, p.y - distance, p.z - distance};
        const double hi[3] = {p.x + distance, p.y + distance, p.z + distance};
        for (std::uint32_t id = 0; id < n && !out.near_end; ++id) {
            double t = 0.0;
            if (!scene.is_degenerate(id) && meets(scene.triangle(id), lo, hi) &&
                line_crossing(scene.triangle(id), ray, t))
                out.near_end = std::fabs(t - end) <= w;
        }
    }
    if (!out.near_end) return out;  // the caller's question is settled (both are needed)
    // Then the segment (cut to where it can still meet the scene) away from its ends.
    const RaySegment segment = clip_to_scene(scene, ray);
    if (segment.empty) return out;
    const double lo[3] = {std::min(segment.a.x, segment.b.x) - distance, std::min(segment.a.y, segment.b.y) - distance,
                          std::min(segment.a.z, segment.b.z) - distance};
    const double hi[3] = {std::max(segment.a.x, segment.b.x) + distance, std::max(segment.a.y, segment.b.y) + distance,
                          std::max(segment.a.z, segment.b.z) + distance};
    for (std::uint32_t id = 0; id < n && !out.inside; ++id) {
        double t = 0.0;
        if (!scene.is_degenerate(id) && meets(scene.triangle(id), lo, hi) && line_crossing(scene.triangle(id), ray, t))
            out.inside = t > double(ray.tnear) + w && t < double(ray.tfar) - w;
    }
    return out;
}

}  // namespace beamtrace::oracle
