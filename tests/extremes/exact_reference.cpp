#include "extremes/exact_reference.hpp"

#include <cmath>

namespace beamtrace::test {

namespace {

struct D3 {
    double x, y, z;
};
D3 d3(Float3 p) { return {p.x, p.y, p.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

template <bool kAny>
Hit trace(const Scene& scene, const Ray& ray, double tol = 0.0) {
    Hit best;
    if (!well_formed(ray)) return best;
    const D3 o = d3(ray.org), d = d3(ray.dir);
    double best_t = double(ray.tfar);
    const auto tris = scene.triangles();
    for (std::uint32_t id = 0; id < tris.size(); ++id) {
        if (scene.is_degenerate(id)) continue;
        const Triangle& tri = tris[id];
        // Moller-Trumbore in double.
        const D3 v0 = d3(tri.v0), e1 = d3(tri.v1) - v0, e2 = d3(tri.v2) - v0;
        const D3 p = cross(d, e2);
        const double det = dot(e1, p);
        if (det == 0.0 || !std::isfinite(det)) continue;
        const double inv = 1.0 / det;
        const D3 s = o - v0;
        const double u = dot(s, p) * inv;
        if (!(u >= -tol && u <= 1.0 + tol)) continue;
        const D3 q = cross(s, e1);
        const double v = dot(d, q) * inv;
        if (!(v >= -tol && u + v <= 1.0 + tol)) continue;
        const double t = dot(e2, q) * inv;
        if (!(t >= double(ray.tnear) && t <= best_t)) continue;
        best_t = t;
        best = Hit{float(t), id, float(u), float(v)};
        if (kAny) return best;
    }
    return best;
}

}  // namespace

bool well_formed(const Ray& ray) {
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(ray.org[k]) || !std::isfinite(ray.dir[k])) return false;
    if (ray.dir.x == 0.0f && ray.dir.y == 0.0f && ray.dir.z == 0.0f) return false;
    if (!std::isfinite(ray.tnear) || std::isnan(ray.tfar)) return false;
    return ray.tnear <= ray.tfar;
}

Hit exact_intersect(const Scene& scene, const Ray& ray) { return trace<false>(scene, ray); }
Hit exact_intersect(const Scene& scene, const Ray& ray, double tolerance) {
    return trace<false>(scene, ray, tolerance);
}
bool exact_occluded(const Scene& scene, const Ray& ray) { return trace<true>(scene, ray).hit(); }

}  // namespace beamtrace::test
