#pragma once
// A workload: the scene, its camera and light, the rays of one mode, and the oracle's answers for
// them. Built once (untimed) and shared by every engine of a benchmark, a picture or a test.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "oracle/embree_oracle.hpp"
#include "scenes/scene_source.hpp"
#include "rays/ray_set.hpp"

namespace beamtrace::workload {

struct WorkloadConfig {
    std::string scene;                     // a scene spec (see scenes::load_scene)
    std::optional<scenes::Camera> camera;  // default: the scene's own
    std::optional<Float3> light;           // default: default_light()
    Mode mode = Mode::primary;
    int width = 1024, height = 1024;
    int ao_rays = 16;
    AoDirections ao_directions;  // random (default) or the PSF directions of VLF-RT
};

struct Workload {
    explicit Workload(scenes::SceneSource s) : source(std::move(s)) {}
    scenes::SceneSource source;
    scenes::Camera camera;
    Float3 light;
    Mode mode = Mode::primary;
    RaySet primary;                                // always made (secondary rays start at its hits)
    std::vector<Hit> primary_hits;                 // the oracle's closest hits of the primary rays
    RaySet rays;                                   // the rays of `mode` (== primary for Mode::primary)
    std::vector<Hit> reference_hits;               // oracle closest hits of `rays` (primary mode)
    std::vector<std::uint8_t> reference_occluded;  // oracle occlusion of `rays` (shadow, ao)
    std::shared_ptr<const oracle::EmbreeOracle> oracle;
};

// Replaces the rays (and their mode: closest hit for Mode::primary, occlusion otherwise) and asks the
// oracle again.
void replace_rays(Workload& workload, RaySet rays);

// Loads the scene (or takes the given one), makes the rays and the oracle's answers.
Workload make_workload(const WorkloadConfig& config);
Workload make_workload(scenes::SceneSource source, const WorkloadConfig& config);

}  // namespace beamtrace::workload
