#include "engines/engine.hpp"

#include <chrono>

namespace beamtrace::workload {

void EngineAnswers::to_slots(const RaySet& rays, bool closest) {
    if (form == Form::slots) return;
    const Form from = form;
    form = Form::slots;
    if (from == Form::rays) {
        if (closest) {
            hits.assign(rays.slots(), Hit{});
            for (std::size_t k = 0; k < ray_slots->size(); ++k) hits[(*ray_slots)[k]] = ray_hits[k];
        } else {
            occluded.assign(rays.slots(), 0);
            for (std::size_t k = 0; k < ray_slots->size(); ++k) occluded[(*ray_slots)[k]] = ray_occluded[k];
        }
        return;
    }
    if (closest) {
        hits.assign(rays.slots(), Hit{});
        for (std::size_t p = 0; p < rays.packets.size(); ++p)
            for (std::uint32_t m = rays.packets[p].active & 0xFFFFu; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                hits[p * 16 + std::size_t(i)] = packet_hits[p].hit(i);
            }
        return;
    }
    occluded.assign(rays.slots(), 0);
    for (std::size_t p = 0; p < rays.packets.size(); ++p)
        for (std::uint32_t m = packet_occluded[p] & rays.packets[p].active & 0xFFFFu; m; m &= m - 1)
            occluded[p * 16 + std::size_t(__builtin_ctz(m))] = 1;
}

void Engine::intersect(const RaySet& rays, std::vector<Hit>& hits, int threads) const {
    EngineAnswers a;
    trace(rays, true, a, threads);
    a.to_slots(rays, true);
    hits = std::move(a.hits);
}

void Engine::occluded(const RaySet& rays, std::vector<std::uint8_t>& occluded, int threads) const {
    EngineAnswers a;
    trace(rays, false, a, threads);
    a.to_slots(rays, false);
    occluded = std::move(a.occluded);
}

double Engine::timed_pass(const RaySet& rays, EngineAnswers& answers, int threads, int) {
    prepare(rays);
    const bool closest = closest_hit(rays.mode);
    const auto start = std::chrono::steady_clock::now();
    trace(rays, closest, answers, threads);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    answers.to_slots(rays, closest);
    return seconds;
}

}  // namespace beamtrace::workload
