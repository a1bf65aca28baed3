#pragma once
// The finely tessellated things standing on the room's desks. Each kind is made of closed meshes and
// has a fixed triangle count near 15,000 whatever its size, so the room's total hardly depends on the
// seed that picks them.
#include <cstddef>

#include "scenes/mesh_builder.hpp"

namespace beamtrace::scenes {

enum class DeskObject { ball, ring, teapot, vase, cup, trefoil_knot, bottle, ring_tower };
inline constexpr int kDeskObjectKinds = 8;

const char* desk_object_name(DeskObject kind);

// Adds `kind` standing on the horizontal surface point `base` (nothing below base.y), inside the
// vertical cylinder of radius `footprint` about it, turned by `yaw_radians` about the vertical.
// Returns the number of triangles added (always desk_object_triangles(kind, coarseness)). A coarseness
// k > 1 divides every tessellation count by k (never below what the shape needs): about k^2 times
// fewer triangles, the same shapes (room-lite).
std::size_t add_desk_object(MeshBuilder& mesh, DeskObject kind, Float3 base, float footprint, float yaw_radians,
                            int coarseness = 1);

std::size_t desk_object_triangles(DeskObject kind, int coarseness = 1);

}  // namespace beamtrace::scenes
