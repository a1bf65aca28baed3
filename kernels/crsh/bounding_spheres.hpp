#pragma once
// The geometry side of CRSH: bounding spheres of triangles and of objects (sets of triangles). Each
// is stored in float and contains its corners exactly: the centre is rounded to float first, the
// radius measured from that centre to every corner in double and rounded up.
#include <span>

#include "beamtrace/scene.hpp"

namespace beamtrace::crsh {

struct Sphere {
    Float3 centre;
    float radius = 0.0f;
};

// The smallest sphere through or around the three corners (the circumsphere of an acute triangle,
// else the sphere on its longest edge), as described above. A triangle of zero area gets the
// sphere about its box centre.
Sphere triangle_sphere(const Triangle& triangle);

// A sphere about the centre of the triangles' box, reaching the farthest corner (not the smallest
// sphere, which the paper computes with Gaertner's algorithm: docs/crsh.md). `triangles` not empty.
Sphere bounding_sphere(std::span<const Triangle> triangles);

// Whether every corner lies inside the sphere (exactly, in double): the property both keep.
bool contains(const Sphere& sphere, const Triangle& triangle);

}  // namespace beamtrace::crsh
