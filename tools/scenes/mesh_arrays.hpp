#pragma once
// A triangle mesh as plain arrays, what every file reader hands to the Scene constructor.
#include <cstdint>
#include <vector>

#include "beamtrace/vec.hpp"

namespace beamtrace::scenes {

struct MeshArrays {
    std::vector<Float3> vertices;
    std::vector<std::uint32_t> indices;  // three per triangle
    unsigned meshes = 1;                 // meshes of the file that gave triangles
    // Per triangle, the mesh it came from (0 .. meshes - 1): empty for a file of one mesh.
    std::vector<std::uint32_t> mesh_of_triangle;
};

}  // namespace beamtrace::scenes
