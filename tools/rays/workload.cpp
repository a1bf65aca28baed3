#include "rays/workload.hpp"

#include <thread>

#include "beamtrace/error.hpp"
#include "engines/parallel.hpp"

namespace beamtrace::workload {

namespace {

int all_threads() { return int(std::max(1u, std::thread::hardware_concurrency())); }

std::vector<Hit> oracle_hits(const oracle::EmbreeOracle& oracle, const RaySet& rays) {
    std::vector<Hit> hits(rays.slots());
    for_packet_ranges(rays.packets.size(), all_threads(), [&](std::size_t b, std::size_t e) {
        for (std::size_t slot = b * 16; slot < e * 16; ++slot)
            if (rays.active(slot)) hits[slot] = oracle.intersect1(rays.ray(slot));
    });
    return hits;
}

std::vector<std::uint8_t> oracle_occlusion(const oracle::EmbreeOracle& oracle, const RaySet& rays) {
    std::vector<std::uint8_t> occluded(rays.slots(), 0);
    for_packet_ranges(rays.packets.size(), all_threads(), [&](std::size_t b, std::size_t e) {
        for (std::size_t slot = b * 16; slot < e * 16; ++slot)
            if (rays.active(slot)) occluded[slot] = oracle.occluded1(rays.ray(slot));
    });
    return occluded;
}

}  // namespace

void WorkloadConfig::validate() const {
    const std::string mode_name = to_string(mode);
    if (lights != 0) {
        if (lights < 1 || lights > 4096) throw Error("--lights must be between 1 and 4096");
        if (light)
            throw Error(
                "--lights and --light cannot be used together: --lights N spreads N lights over the scene's "
                "upper box, --light X,Y,Z places one");
        if (area_light)
            throw Error("--area-light and --lights cannot be used together: the shadow rays go to one or the other");
        if (mode != Mode::shadow)
            throw Error("--lights applies to shadow rays only (--mode shadow), not to --mode " + mode_name);
    }
    if (area_light) {
        if (light)
            throw Error("--area-light and --light cannot be used together: the shadow rays go to one or the other");
        if (mode != Mode::shadow)
            throw Error("--area-light applies to shadow rays only (--mode shadow), not to --mode " + mode_name);
    }
}

ShadowLights shadow_lights(const WorkloadConfig& config, const Box& bounds, const scenes::Camera& camera) {
    ShadowLights s;
    const auto upper = [&] {
        Float3 up = camera.up;
        if (!(dot(up, up) > 0.0f)) up = camera.basis().up;
        return upper_box(bounds, up);
    };
    if (config.mode == Mode::shadow && config.area_light)
        s.area = area_light(upper());
    else if (config.mode == Mode::shadow && config.lights > 0)
        s.points = spread_lights(upper(), config.lights);
    else
        s.points = {config.light ? *config.light : default_light(camera, bounds)};
    return s;
}

RaySet make_mode_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& hits,
                      const WorkloadConfig& config, const ShadowLights& lights) {
    RaySet rays;
    switch (config.mode) {
        case Mode::primary:
            rays = primary;
            break;
        case Mode::shadow:
            if (lights.area)
                rays = make_area_shadow_rays(scene, primary, hits, *lights.area);
            else if (config.lights > 0)
                rays = make_shadow_rays(scene, primary, hits, lights.points);
            else
                rays = make_shadow_rays(scene, primary, hits, lights.points.at(0));
            break;
        case Mode::ao:
            rays = make_ao_rays(scene, primary, hits, config.ao_rays, config.ao_directions);
            break;
        case Mode::diffuse:
            rays = make_diffuse_rays(scene, primary, hits);
            break;
    }
    if (config.order == Order::input) return rays;  // moved (a conditional expression would copy it)
    return reorder(rays, config.order);
}

int point_lights(const Workload& w) { return w.mode == Mode::shadow ? w.lights.count() : 0; }

std::string describe_rays(Mode mode, Order order, int point_lights, bool area_light) {
    std::string text = std::string("mode ") + to_string(mode);
    if (mode == Mode::shadow)
        text += area_light ? " (area light)"
                           : " (" + std::to_string(point_lights) + (point_lights == 1 ? " light)" : " lights)");
    return text + ", order " + to_string(order);
}

void release_untraced(Workload& w) {
    w.primary = RaySet();
    std::vector<Hit>().swap(w.primary_hits);
    std::vector<std::uint32_t>().swap(w.rays.pixel);
}

void replace_rays(Workload& w, RaySet rays) {
    w.mode = rays.mode;
    w.rays = std::move(rays);
    w.reference_hits.clear();
    w.reference_occluded.clear();
    if (closest_hit(w.mode))
        w.reference_hits = oracle_hits(*w.oracle, w.rays);
    else
        w.reference_occluded = oracle_occlusion(*w.oracle, w.rays);
}

Workload make_workload(const WorkloadConfig& config) {
    config.validate();
    return make_workload(scenes::load_scene(config.scene), config);
}

Workload make_workload(scenes::SceneSource source, const WorkloadConfig& config) {
    config.validate();
    Workload w(std::move(source));
    const Scene& scene = w.source.scene;
    w.camera = config.camera ? *config.camera : w.source.camera;
    w.light = config.light ? *config.light : default_light(w.camera, scene.bounds());
    w.lights = shadow_lights(config, scene.bounds(), w.camera);
    w.mode = config.mode;
    w.order = config.order;
    w.oracle = std::make_shared<oracle::EmbreeOracle>(scene);
    w.primary = make_primary_rays(w.camera, config.width, config.height);
    w.primary_hits = oracle_hits(*w.oracle, w.primary);
    w.rays = make_mode_rays(scene, w.primary, w.primary_hits, config, w.lights);
    if (config.mode == Mode::primary && config.order == Order::input)
        w.reference_hits = w.primary_hits;
    else if (closest_hit(config.mode))
        w.reference_hits = oracle_hits(*w.oracle, w.rays);
    else
        w.reference_occluded = oracle_occlusion(*w.oracle, w.rays);
    return w;
}

}  // namespace beamtrace::workload
