#pragma once
// Triangle meshes from files (OBJ, PLY, OFF, STL, glTF and anything else Assimp reads).
#include <string>

#include "scenes/scene_source.hpp"

namespace beamtrace::scenes {

// Reads every mesh of the file into one scene (triangulated, identical vertices joined, node
// transforms applied; points and lines dropped). OFF files (by extension or content) are read by
// our own parser (scenes/off_file.hpp: the file's vertices as they are); PLY headers are checked
// (scenes/ply_header.hpp) before Assimp reads the file. The camera is frame_from_outside(bounds), the name
// the file name. Throws beamtrace::Error, one line naming the file, for: a missing or unreadable file
// ("cannot open FILE: reason"), an empty file, any Assimp failure, a file with no triangles ("FILE
// contains no triangles"), and broken data (bad indices, NaN or infinite coordinates, counts larger
// than the file, truncation).
SceneSource load_mesh_file(const std::string& path);

}  // namespace beamtrace::scenes
