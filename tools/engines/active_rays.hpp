#pragma once
// The active rays of a ray set side by side (for the span-of-rays queries) and the slot of each.
#include <cstdint>
#include <vector>

#include "beamtrace/query.hpp"
#include "engines/engine.hpp"
#include "rays/ray_set.hpp"

namespace beamtrace::workload {

struct ActiveRays {
    std::vector<Ray> rays;
    std::vector<std::uint32_t> slots;
};

inline ActiveRays active_rays(const RaySet& set) {
    ActiveRays a;
    a.rays.reserve(set.ray_count);
    a.slots.reserve(set.ray_count);
    for (std::size_t p = 0; p < set.packets.size(); ++p)
        for (std::uint32_t m = set.packets[p].active & 0xFFFFu; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            a.rays.push_back(set.packets[p].ray(i));
            a.slots.push_back(std::uint32_t(p * 16 + std::size_t(i)));
        }
    return a;
}

// The answers of an accelerator's span-of-rays queries (the query contract) to the active rays, by
// ray (EngineAnswers::Form::rays, the slots `in`'s): what kd1, stream, crsh and rah do.
template <class Accelerator>
void answer_rays(const Accelerator& accelerator, const ActiveRays& in, bool closest, EngineAnswers& a,
                 const QueryOptions& options) {
    a.form = EngineAnswers::Form::rays;
    a.ray_slots = &in.slots;
    if (closest) {
        a.ray_hits.resize(in.rays.size());
        accelerator.intersect(in.rays, a.ray_hits, options);
    } else {
        a.ray_occluded.resize(in.rays.size());
        accelerator.occluded(in.rays, a.ray_occluded, options);
    }
}

// The active rays of a ray set, made once outside the timed passes (Engine::prepare).
struct PreparedRays {
    ActiveRays active;
    const RaySet* for_set = nullptr;
    const Packet16* packets = nullptr;

    bool ready_for(const RaySet& rays) const {
        return for_set == &rays && packets == rays.packets.data() && active.rays.size() == rays.ray_count;
    }
    // Forgets the rays prepared (an engine's build() does: a later ray set may sit at the same
    // address with the same count, and the identity above would take it for the old one).
    void forget() { *this = PreparedRays{}; }
    void prepare(const RaySet& rays) {
        if (ready_for(rays)) return;
        active = active_rays(rays);
        for_set = &rays;
        packets = rays.packets.data();
    }
    // answer_rays() over the prepared rays, or over rays made here (and spread into slots at once,
    // while they live) when the set was not prepared.
    template <class Accelerator>
    void answer(const Accelerator& accelerator, const RaySet& rays, bool closest, EngineAnswers& a,
                const QueryOptions& options) const {
        if (ready_for(rays)) {
            answer_rays(accelerator, active, closest, a, options);
            return;
        }
        const ActiveRays made = active_rays(rays);
        answer_rays(accelerator, made, closest, a, options);
        a.to_slots(rays, closest);
    }
};

}  // namespace beamtrace::workload
