// The brute-force reference: every non-degenerate triangle against the ray, scalar.
#include "beamtrace/kdtree.hpp"
#include "common/ray_validity.hpp"
#include "common/triangle_reference.hpp"

namespace beamtrace {

Hit intersect_brute_force(const Scene& scene, const Ray& ray) {
    Hit best;
    if (!describes_segment(ray)) return best;
    WatertightRay w = make_watertight_ray(ray);
    const std::size_t n = scene.triangle_count();
    for (std::uint32_t t = 0; t < n; ++t) {
        if (scene.is_degenerate(t)) continue;
        TriangleHit h;
        if (intersect_triangle(w, scene.triangle(t), h) && h.t < best.t) {
            best = Hit{h.t, t, h.u, h.v};
            w.tfar = h.t;
        }
    }
    return best;
}

bool occluded_brute_force(const Scene& scene, const Ray& ray) {
    if (!describes_segment(ray)) return false;
    const WatertightRay w = make_watertight_ray(ray);
    const std::size_t n = scene.triangle_count();
    for (std::uint32_t t = 0; t < n; ++t) {
        TriangleHit h;
        if (!scene.is_degenerate(t) && intersect_triangle(w, scene.triangle(t), h)) return true;
    }
    return false;
}

}  // namespace beamtrace
