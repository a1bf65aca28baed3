#include "crsh/bounding_spheres.hpp"

#include <algorithm>

#include "crsh/vec3d.hpp"

namespace beamtrace::crsh {

namespace {

Float3 to_float(Vec3d p) { return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)}; }

// The radius that reaches `corner` from the float centre, rounded up (the small relative pad covers
// the double subtraction and square root).
double reach(Float3 centre, Float3 corner) { return length(Vec3d(corner) - Vec3d(centre)) * (1.0 + 1e-14); }

}  // namespace

Sphere triangle_sphere(const Triangle& t) {
    const Vec3d a(t.v0), b(t.v1), c(t.v2);
    const Vec3d ab = b - a, ac = c - a, bc = c - b;
    Vec3d centre;
    const Vec3d n = cross(ab, ac);
    const double n2 = dot(n, n);
    if (!(n2 > 0.0) || !std::isfinite(n2)) {
        const Float3 lo = min(min(t.v0, t.v1), t.v2), hi = max(max(t.v0, t.v1), t.v2);
        centre = (Vec3d(lo) + Vec3d(hi)) * 0.5;
    } else if (dot(ab, ac) <= 0.0) {
        centre = (b + c) * 0.5;  // obtuse or right at a: the sphere on bc
    } else if (dot(ab * -1.0, bc) <= 0.0) {
        centre = (a + c) * 0.5;
    } else if (dot(ac, bc) <= 0.0) {
        centre = (a + b) * 0.5;
    } else {
        // Circumcentre: a + (|ac|^2 (n x ab) + |ab|^2 (ac x n)) / (2 |n|^2).
        centre = a + (cross(n, ab) * dot(ac, ac) + cross(ac, n) * dot(ab, ab)) * (0.5 / n2);
    }
    Sphere s;
    s.centre = to_float(centre);
    s.radius = round_up(std::max({reach(s.centre, t.v0), reach(s.centre, t.v1), reach(s.centre, t.v2)}));
    return s;
}

Sphere bounding_sphere(std::span<const Triangle> triangles) {
    Box box;
    for (const Triangle& t : triangles) {
        box.extend(t.v0);
        box.extend(t.v1);
        box.extend(t.v2);
    }
    Sphere s;
    s.centre = to_float((Vec3d(box.lower) + Vec3d(box.upper)) * 0.5);
    double r = 0.0;
    for (const Triangle& t : triangles)
        r = std::max({r, reach(s.centre, t.v0), reach(s.centre, t.v1), reach(s.centre, t.v2)});
    s.radius = round_up(r);
    return s;
}

bool contains(const Sphere& s, const Triangle& t) {
    const double r = s.radius;
    for (const Float3& p : {t.v0, t.v1, t.v2})
        if (length(Vec3d(p) - Vec3d(s.centre)) > r) return false;
    return true;
}

}  // namespace beamtrace::crsh
