#pragma once
// Double-precision geometry for judging disagreements between two ray tracers: how close a ray
// segment comes to the edges of a triangle, and how close the ray's line crosses a triangle to the
// ends of its segment.
#include <cstdint>

#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"

namespace beamtrace::oracle {

struct Double3 {
    double x = 0, y = 0, z = 0;
};

inline Double3 to_double(Float3 p) { return {p.x, p.y, p.z}; }

// Shortest distance between the segments [p0, p1] and [q0, q1] (either may be a single point).
double segment_distance(Double3 p0, Double3 p1, Double3 q0, Double3 q1);

// The part of a ray that can matter for a scene: the points org + t * dir for t in
// [tnear, min(tfar, t_exit)], where beyond t_exit the ray can no longer come near the scene's box
// (t_exit = (|org - box centre| + box diagonal) / |dir|). Empty for NaN or reversed rays and for
// rays that start beyond t_exit.
struct RaySegment {
    Double3 a, b;
    bool empty = true;
};
RaySegment clip_to_scene(const Scene& scene, const Ray& ray);

// Shortest distance between the segment and the three edges of a triangle (infinity if the
// segment is empty).
double edge_distance(const Triangle& triangle, const RaySegment& segment);

// Distance between the point where the ray's line (org + t dir, any t) crosses the triangle and the
// nearer of the segment's two ends (org + tnear dir, org + tfar dir; an infinite end is infinitely
// far): infinity when the line misses the triangle or runs parallel to its plane (a line in the
// plane passes its edges: edge_distance), or the ray holds NaNs. Computed in double: a line that
// crosses within double rounding of an edge may count as missing (edge_distance sees those).
double end_distance(const Triangle& triangle, const Ray& ray);

// The distance below which a disagreement counts as grazing: 1e-5 times the scene box diagonal.
double grazing_distance(const Scene& scene);

// Whether the segment passes within `distance` of an edge of any non-degenerate triangle of the
// scene. Brute force over every triangle (with a box rejection test first).
bool near_edge_of_any(const Scene& scene, const RaySegment& segment, double distance);

// Where the ray's line crosses the scene's non-degenerate triangles on or near its segment (double
// precision, brute force over every triangle): near_end, some crossing lies within `distance` of an
// end of the segment (either side of tnear or tfar); inside, some crossing lies on the segment
// farther than `distance` from both ends. Both false for a ray with NaNs or tnear > tfar; inside is
// only searched for (and otherwise false) when near_end holds.
struct EndCrossings {
    bool near_end = false;
    bool inside = false;
};
EndCrossings end_crossings(const Scene& scene, const Ray& ray, double distance);

}  // namespace beamtrace::oracle
