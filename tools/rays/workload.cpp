#include "rays/workload.hpp"

#include <thread>

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

void replace_rays(Workload& w, RaySet rays) {
    w.mode = rays.mode;
    w.rays = std::move(rays);
    w.reference_hits.clear();
    w.reference_occluded.clear();
    if (w.mode == Mode::primary)
        w.reference_hits = oracle_hits(*w.oracle, w.rays);
    else
        w.reference_occluded = oracle_occlusion(*w.oracle, w.rays);
}

Workload make_workload(const WorkloadConfig& config) { return make_workload(scenes::load_scene(config.scene), config); }

Workload make_workload(scenes::SceneSource source, const WorkloadConfig& config) {
    Workload w(std::move(source));
    const Scene& scene = w.source.scene;
    w.camera = config.camera ? *config.camera : w.source.camera;
    w.light = config.light ? *config.light : default_light(w.camera, scene.bounds());
    w.mode = config.mode;
    w.oracle = std::make_shared<oracle::EmbreeOracle>(scene);
    w.primary = make_primary_rays(w.camera, config.width, config.height);
    w.primary_hits = oracle_hits(*w.oracle, w.primary);
    switch (config.mode) {
        case Mode::primary:
            w.rays = w.primary;
            w.reference_hits = w.primary_hits;
            break;
        case Mode::shadow:
            w.rays = make_shadow_rays(scene, w.primary, w.primary_hits, w.light);
            w.reference_occluded = oracle_occlusion(*w.oracle, w.rays);
            break;
        case Mode::ao:
            w.rays = make_ao_rays(scene, w.primary, w.primary_hits, config.ao_rays, config.ao_directions);
            w.reference_occluded = oracle_occlusion(*w.oracle, w.rays);
            break;
    }
    return w;
}

}  // namespace beamtrace::workload
