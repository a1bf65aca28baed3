#pragma once
// The scalar reference of the watertight ray/triangle test. Every SIMD kernel must return exactly
// (bit for bit) what this returns for each of its lanes.
#include "beamtrace/scene.hpp"
#include "common/watertight_ray.hpp"

namespace beamtrace {

struct TriangleHit {
    float t, u, v;
};

// Hit if the ray meets the triangle at tnear <= t <= tfar (edges and corners included; triangles of
// zero area never). u, v: the barycentric weights of v1 and v2 (see Hit in beamtrace/ray.hpp).
bool intersect_triangle(const WatertightRay& ray, const Triangle& tri, TriangleHit& hit);

// The edge functions recomputed in double precision when one of them is exactly zero in float
// (the paper's fallback that makes the test watertight). Shared by the SIMD kernels' slow lanes.
void watertight_edges_double(float ax, float ay, float bx, float by, float cx, float cy, float& u, float& v, float& w);

}  // namespace beamtrace
