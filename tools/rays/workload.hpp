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
    // Shadow mode only: 0 = one light (`light`); N >= 1 = N lights spread over the upper box
    // (spread_lights), N rays per primary hit.
    int lights = 0;
    bool area_light = false;  // shadow mode only: one ray per primary hit to a point of area_light()
    // Of the rays of `mode` (the primary rays that secondary rays start from stay in image order).
    Order order = Order::input;

    // Throws beamtrace::Error naming the options that do not go together (--lights with --light,
    // --area-light with either, --lights or --area-light outside shadow mode) or are out of range.
    void validate() const;
};

// Where a workload's shadow rays go: one point light, several, or the area light.
struct ShadowLights {
    std::vector<Float3> points;     // one or more point lights (empty with the area light)
    std::optional<AreaLight> area;  // with --area-light
    // The point lights: 0 with the area light.
    int count() const { return area ? 0 : int(points.size()); }
};
// The lights of the config's shadow rays, for a scene's box and camera (the single light defaults
// to default_light(); the upper box is taken along the camera's up).
ShadowLights shadow_lights(const WorkloadConfig& config, const Box& bounds, const scenes::Camera& camera);

// The rays of config.mode made from the primary rays (in image order) and closest hits given (the
// oracle's in a workload, an engine's in a picture), put in config.order. For Mode::primary, the
// primary rays themselves.
RaySet make_mode_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& primary_hits,
                      const WorkloadConfig& config, const ShadowLights& lights);

struct Workload {
    explicit Workload(scenes::SceneSource s) : source(std::move(s)) {}
    scenes::SceneSource source;
    scenes::Camera camera;
    Float3 light;         // the single point light (default_light() unless given)
    ShadowLights lights;  // where the shadow rays go (shadow mode; else the single light)
    Mode mode = Mode::primary;
    Order order = Order::input;
    RaySet primary;                                // always made (secondary rays start at its hits)
    std::vector<Hit> primary_hits;                 // the oracle's closest hits of the primary rays
    RaySet rays;                                   // the rays of `mode` in `order` (primary mode: the primary rays)
    std::vector<Hit> reference_hits;               // oracle closest hits of `rays` (primary, diffuse)
    std::vector<std::uint8_t> reference_occluded;  // oracle occlusion of `rays` (shadow, ao)
    std::shared_ptr<const oracle::EmbreeOracle> oracle;
};

// Point lights of the workload's shadow rays: 1 (--light or the default), N (--lights N), 0 with the
// area light and in the other modes.
int point_lights(const Workload& workload);
// The workload facts for headers: "mode shadow (4 lights), order shuffled", "mode shadow (area
// light), order input", "mode diffuse, order input".
std::string describe_rays(Mode mode, Order order, int point_lights, bool area_light);

// Replaces the rays (and their mode: closest hit when closest_hit(mode), occlusion otherwise) and asks
// the oracle again.
void replace_rays(Workload& workload, RaySet rays);

// Frees what only the making of the rays and the pictures read: the primary rays and their hits
// (the rays of the mode and the oracle's answers to them stay) and the rays' pixel indices (left
// empty). The bench calls it before building its engines, so that their memory is measured next to
// no more than the rays they trace (room's 16.8 M AO rays: 59 MB of primary rays and hits and 67 MB
// of pixels). Nothing may read workload.primary, primary_hits or rays.pixel afterwards.
void release_untraced(Workload& workload);

// Loads the scene (or takes the given one), makes the rays and the oracle's answers. Checks the config
// first (WorkloadConfig::validate).
Workload make_workload(const WorkloadConfig& config);
Workload make_workload(scenes::SceneSource source, const WorkloadConfig& config);

}  // namespace beamtrace::workload
