#pragma once
// Where a scene comes from: a procedural generator or a mesh file, chosen by a short text spec such
// as "room:2" or "../shared/scenes/bunny00.off". This is what --scene means in every tool.
#include <cstdint>
#include <string>
#include <vector>

#include "beamtrace/scene.hpp"
#include "scenes/camera.hpp"

namespace beamtrace::scenes {

struct SceneSource {
    std::string name;  // "room:1", "random:1000", "tetra:6", or the file name for a mesh file
    Scene scene;
    Camera camera;  // a default view: procedural default, or frame_from_outside for files
    std::string description;
    // The scene's objects, when it has a natural partition (room: each piece of furniture and desk
    // object; sphereflake: each sphere; tetra: groups of 16 tetrahedra; files: each mesh): the object
    // id of every triangle. Empty: no partition known (the whole scene is one object). For engines
    // that cull by object (crsh); the library's Scene knows nothing of it.
    std::vector<std::uint32_t> object_of_triangle = {};
};

// spec: "random:N", "tetra:LEVEL", "sphereflake:LEVEL", "room" / "room:SEED", or a path to a mesh file
// (anything Assimp reads: OBJ, PLY, OFF, STL, glTF, ...). Generator names win over file names: write
// "./room" for a file called room. Throws beamtrace::Error with one clear line for an unknown
// generator, a bad parameter, a missing or unreadable file, a file without triangles, any Assimp
// failure.
SceneSource load_scene(const std::string& spec);

// One line per accepted spec form, for --help texts and error messages.
std::string scene_spec_help();

}  // namespace beamtrace::scenes
