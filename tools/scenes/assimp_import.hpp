#pragma once
// Reading a mesh file with Assimp (triangulated, identical vertices joined, node transforms applied,
// points and lines dropped), in this process. Assimp trusts its input: this Debian build aborts on
// failed internal assertions for some malformed files, so load_mesh_file runs it in a child process
// (scenes/isolated_import.hpp) and only tests call it directly.
#include <string>

#include "scenes/mesh_arrays.hpp"

namespace beamtrace::scenes {

// Throws beamtrace::Error, one line naming the file: Assimp's error, "FILE contains no triangles",
// an index out of range, a NaN or infinite coordinate, more than 2^32 vertices.
MeshArrays import_with_assimp(const std::string& path);

}  // namespace beamtrace::scenes
