#pragma once
// The procedural animations of `beamtrace bench --animation`: a static scene (by default `room`) with
// some of its parts set in motion, as an AnimatedScene whose keyframes lie at uniform times over
// [0, 1] (Embree's motion blur needs uniform time steps), and a camera that may move.
//
//   spin        up to 8 of the scene's small objects (the ones nearest the camera's target) each turn
//               once about the vertical axis through its box centre (13 keyframes, 30 degrees apart)
//   comet       the small object nearest the camera's target flies across the scene in a straight line
//               (2 keyframes)
//   party:N     N tessellated spheres (N in 1..256, about 1,300 triangles each) added to the scene drift
//               through it along random paths (9 keyframes)
//   flythrough  nothing moves (2 identical keyframes); the camera moves across the scene
//
// "Small objects" are the parts of SceneSource::object_of_triangle with at least 100 triangles and at
// most 5% of the scene's: in `room`, its 68 desk objects and the 4 bookshelf boards with their books. Deterministic: the same spec and base scene
// give bit-identical animations on every run.
#include <cstdint>
#include <string>
#include <vector>

#include "beamtrace/animated_scene.hpp"
#include "scenes/camera.hpp"
#include "scenes/scene_source.hpp"

namespace beamtrace::scenes {

struct AnimationSource {
    std::string name;         // the spec: "spin", "comet", "party:8", "flythrough"
    std::string base_scene;   // the static scene's name (SceneSource::name)
    std::string description;  // one line for reports
    AnimatedScene scene;      // keyframes at k / (K - 1), k = 0 .. K - 1
    Camera camera_start, camera_end;  // equal unless the camera moves

    // The camera at time t in [0, 1]: eye and target moved linearly from start to end.
    Camera camera(float t) const;
};

// Animates `base` (a loaded scene) as the spec says. Throws beamtrace::Error for an unknown name,
// a bad parameter (party:0, party:x), or a scene without small objects (spin, comet).
AnimationSource make_animation(const std::string& spec, const SceneSource& base);

// One line per animation, for --help texts and error messages.
std::string animation_spec_help();

// The small objects of a scene (see above), nearest to `target` first (by their box centres).
std::vector<std::uint32_t> small_objects(const SceneSource& source, Float3 target);

}  // namespace beamtrace::scenes
