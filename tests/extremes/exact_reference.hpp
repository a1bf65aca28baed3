#pragma once
// Exact geometry, as near as double precision gets: the closest hit of a ray over every
// non-degenerate triangle of a scene, computed in double from the float inputs (which double holds
// exactly). The reference the extremes tests hold every engine (and the oracle) against, beside the
// oracle itself. Brute force: meant for small scenes or a few thousand rays.
#include <cstdint>

#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"

namespace beamtrace::test {

// Closest hit with tnear <= t <= tfar (edges included). Rays that describe no segment (a NaN, an
// infinite origin or direction component, a zero direction, tnear > tfar) report no hit: the
// contract of beamtrace/ray.hpp. A ray lying in a triangle's plane never hits it.
Hit exact_intersect(const Scene& scene, const Ray& ray);
// The same with triangles grown by `tolerance` in barycentric terms (u, v >= -tolerance, u + v <=
// 1 + tolerance): a conservative answer for rays aimed exactly at edges and vertices, where double
// precision alone can still slip between two triangles.
Hit exact_intersect(const Scene& scene, const Ray& ray, double tolerance);
bool exact_occluded(const Scene& scene, const Ray& ray);

// Whether a ray describes a segment at all (the same rule as the library's contract).
bool well_formed(const Ray& ray);

}  // namespace beamtrace::test
