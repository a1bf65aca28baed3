#pragma once
// Whether the rays of a call share a point: all end at one (occlusion rays towards a point light,
// classified from the light) or all start at one (camera rays). Then a light buffer, a direction
// map around that point, classifies them (the static part's and the moving part's alike).
#include <cmath>
#include <cstddef>
#include <span>

#include "beamtrace/ray.hpp"
#include "beamtrace/vec.hpp"
#include "common/ray_validity.hpp"

namespace beamtrace::raycls {

enum class Frame { space, from_start, from_end };

struct SharedPoint {
    Frame frame = Frame::space;
    Box points;  // the box of the shared end or start points (empty for Frame::space)
};

inline float origin_of(const Ray& r, int k) { return r.org[k] + r.tnear * r.dir[k]; }

// The rays' shared end point (looked for when `occlusion` and every segment is finite) or else
// their shared start point: one whose box of points has a diagonal of at most `size`. Calls of
// fewer than min_rays valid-or-not rays share nothing.
inline SharedPoint find_shared_point(std::span<const Ray> rays, bool occlusion, float size, std::size_t min_rays) {
    if (rays.size() < min_rays) return {};
    Box starts, ends;
    bool finite_ends = occlusion;
    std::size_t valid = 0;
    for (const Ray& r : rays) {
        if (!describes_segment(r)) continue;
        ++valid;
        starts.extend(Float3{origin_of(r, 0), origin_of(r, 1), origin_of(r, 2)});
        if (finite_ends) {
            if (r.tfar == kInfinity) {
                finite_ends = false;
                continue;
            }
            ends.extend(r.org + r.dir * r.tfar);
        }
    }
    if (valid == 0) return {};
    const auto small = [size](const Box& b) { return !b.empty() && std::isfinite(b.diagonal()) && b.diagonal() <= size; };
    if (finite_ends && small(ends)) return {Frame::from_end, ends};
    if (small(starts)) return {Frame::from_start, starts};
    return {};
}

}  // namespace beamtrace::raycls
