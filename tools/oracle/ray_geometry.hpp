#pragma once
// Double-precision geometry for judging disagreements between two ray tracers: how close a ray
// segment comes to the edges of a triangle.
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

// The distance below which a disagreement counts as grazing: 1e-5 times the scene box diagonal.
double grazing_distance(const Scene& scene);

// Whether the segment passes within `distance` of an edge of any non-degenerate triangle of the
// scene. Brute force over every triangle (with a box rejection test first).
bool near_edge_of_any(const Scene& scene, const RaySegment& segment, double distance);

}  // namespace beamtrace::oracle
