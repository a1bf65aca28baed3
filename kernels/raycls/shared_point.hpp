#pragma once
// Whether the rays of a call share a point: all end at one (occlusion rays towards a point light,
// classified from the light) or all start at one (camera rays). Then a light buffer, a direction
// map around that point, classifies them (the static part's and the moving part's alike).
#include <cmath>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "beamtrace/ray.hpp"
#include "beamtrace/vec.hpp"
#include "common/ray_validity.hpp"

namespace beamtrace::raycls {

enum class Frame { space, from_start, from_end };

struct SharedPoint {
    Frame frame = Frame::space;
    Box points;  // the box of the shared end or start points (empty for Frame::space)
};

// The largest box of points that counts as one shared point, as a fraction of the scene's diagonal.
// Shadow rays as renderers make them end just short of their light (tfar = 1 - 1e-4 with dir = light -
// origin: ends up to 1e-4 of the ray's length apart, about 3.5e-4 of the diagonal for lights above a
// room). A light buffer's apex is the box of the points it was made for, grown by kApexMarginFraction
// of the diagonal (so later calls around the same light reuse it): its candidate sets grow fast with
// the apex (room's default light: 7.1 M entries with a margin of 1/16384 of the diagonal, 13.8 M with
// 1/4096), so the margin stays small whatever the points' box may be.
inline constexpr float kSharedPointFraction = 1.0f / 1024.0f;
inline constexpr float kApexMarginFraction = 1.0f / 16384.0f;

inline float origin_of(const Ray& r, int k) { return r.org[k] + r.tnear * r.dir[k]; }

// The rays' shared end points (looked for when `occlusion` and every segment is finite) or else
// their shared start points: at most max_points points, each a box of points with a diagonal of at
// most `size`, and every ray that describes a segment at one of them (`of[i]`: ray i's point; empty
// when there is one point). Shadow rays of one hit towards N point lights share N end points. Calls of
// fewer than min_rays valid-or-not rays share nothing. Points are made greedily in the rays' order
// (a ray joins the last point it joined if it can, else the first that stays small, else a new one).
struct SharedPoints {
    Frame frame = Frame::space;
    std::vector<Box> points;
    std::vector<std::uint8_t> of;
};

inline SharedPoints find_shared_points(std::span<const Ray> rays, bool occlusion, float size, std::size_t min_rays,
                                       std::size_t max_points) {
    if (rays.size() < min_rays || max_points == 0) return {};
    max_points = std::min<std::size_t>(max_points, 256);  // `of` holds a byte
    const auto small = [size](const Box& b) { return !b.empty() && std::isfinite(b.diagonal()) && b.diagonal() <= size; };
    const auto gather = [&](Frame frame, auto point_of) -> SharedPoints {
        SharedPoints s;
        s.frame = frame;
        if (max_points > 1) s.of.assign(rays.size(), 0);
        std::size_t last = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Ray& r = rays[i];
            if (!describes_segment(r)) continue;
            if (frame == Frame::from_end && r.tfar == kInfinity) return {};
            const Float3 p = point_of(r);
            auto joins = [&](std::size_t c) {
                if (!s.points[c].contains(p)) {  // (most points of a light fall inside its box once it has grown)
                    Box grown = s.points[c];
                    grown.extend(p);
                    if (!small(grown)) return false;
                    s.points[c] = grown;
                }
                last = c;
                return true;
            };
            bool placed = !s.points.empty() && joins(last);
            for (std::size_t c = 0; !placed && c < s.points.size(); ++c) placed = c != last && joins(c);
            if (!placed) {
                Box one;
                one.extend(p);
                if (s.points.size() == max_points || !small(one)) return {};
                s.points.push_back(one);
                last = s.points.size() - 1;
            }
            if (!s.of.empty()) s.of[i] = std::uint8_t(last);
        }
        if (s.points.empty()) return {};  // no ray describes a segment
        if (s.points.size() == 1) s.of.clear();
        return s;
    };
    if (occlusion) {
        SharedPoints ends = gather(Frame::from_end, [](const Ray& r) { return r.org + r.dir * r.tfar; });
        if (ends.frame != Frame::space) return ends;
    }
    return gather(Frame::from_start,
                  [](const Ray& r) { return Float3{origin_of(r, 0), origin_of(r, 1), origin_of(r, 2)}; });
}

// One shared end or start point (find_shared_points with one point at most).
inline SharedPoint find_shared_point(std::span<const Ray> rays, bool occlusion, float size, std::size_t min_rays) {
    const SharedPoints s = find_shared_points(rays, occlusion, size, min_rays, 1);
    if (s.frame == Frame::space) return {};
    return {s.frame, s.points[0]};
}

}  // namespace beamtrace::raycls
