// The Crsh object and its query contract: every span call builds the hierarchy of its rays and
// traverses it; single rays and packets are span calls of their rays.
#include "beamtrace/crsh.hpp"

#include <chrono>
#include <string>
#include <vector>

#include <tbb/task_arena.h>

#include "beamtrace/error.hpp"
#include "common/query_runner.hpp"
#include "crsh/crsh_impl.hpp"
#include "crsh/ray_hierarchy.hpp"
#include "crsh/traversal.hpp"

namespace beamtrace {

namespace {

template <bool kOcclusion>
void trace(const Crsh::Impl& impl, const CrshSettings& settings, std::span<const Ray> rays, Hit* hits,
           std::uint8_t* occluded, const QueryOptions& options) {
    const bool parallel = options.threads > 1;
    QueryCounters* counters = options.counters;
    auto body = [&] {
        const crsh::RayHierarchy h = crsh::build_ray_hierarchy(rays, settings, impl.scene.bounds(), parallel, counters);
        if (counters) {
            const auto start = std::chrono::steady_clock::now();
            crsh::traverse<kOcclusion, true>(impl, settings.object_spheres, rays, h, hits, occluded, parallel,
                                             counters);
            counters->crsh.traversal_ns += static_cast<std::uint64_t>(
                std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count());
        } else {
            crsh::traverse<kOcclusion, false>(impl, settings.object_spheres, rays, h, hits, occluded, parallel,
                                              nullptr);
        }
    };
    if (!parallel) {
        body();
        return;
    }
    tbb::task_arena arena(options.threads);
    arena.execute(body);
}

// The packets' lanes as rays; inactive lanes become rays that describe no segment (no hit).
std::vector<Ray> lanes_as_rays(std::span<const Packet16> packets) {
    std::vector<Ray> rays(packets.size() * 16);
    for (std::size_t p = 0; p < packets.size(); ++p)
        for (int i = 0; i < 16; ++i)
            if ((packets[p].active >> i) & 1u)
                rays[p * 16 + std::size_t(i)] = packets[p].ray(i);
            else
                rays[p * 16 + std::size_t(i)].dir = Float3{0, 0, 0};
    return rays;
}

}  // namespace

void CrshSettings::validate() const {
    if (fanout < 2 || fanout > 64)
        throw Error("CrshSettings: fanout must be between 2 and 64, not " + std::to_string(fanout));
    if (levels < 1 || levels > QueryCounters::Crsh::kMaxLevels)
        throw Error("CrshSettings: levels must be between 1 and " + std::to_string(QueryCounters::Crsh::kMaxLevels) +
                    ", not " + std::to_string(levels));
    if (key_position_bits < 0 || key_position_bits > 10)
        throw Error("CrshSettings: key_position_bits must be between 0 and 10, not " +
                    std::to_string(key_position_bits));
}

Crsh::Crsh(const Scene& scene, const CrshSettings& settings) : settings_(settings) {
    settings.validate();
    impl_ = std::make_shared<const Impl>(crsh::make_impl(scene, settings.object_of_triangle));
    settings_.object_of_triangle = {};
}

Crsh Crsh::with_key(CrshKey key) const {
    CrshSettings s = settings_;
    s.key = key;
    return Crsh(impl_, s);
}

const Scene& Crsh::scene() const { return impl_->scene; }
const CrshStats& Crsh::stats() const { return impl_->stats; }

std::uint64_t Crsh::predicted_top_level_tests(std::size_t rays) const {
    std::uint64_t nodes = rays;
    const std::uint64_t f = static_cast<std::uint64_t>(settings_.fanout);
    for (int l = 0; l < settings_.levels; ++l) nodes = (nodes + f - 1) / f;
    const std::uint64_t per_node =
        settings_.object_spheres ? impl_->stats.objects + impl_->stats.largest_object : impl_->triangles.size();
    return nodes * per_node;
}

Hit Crsh::intersect(const Ray& ray) const {
    Hit hit;
    intersect(std::span<const Ray>(&ray, 1), std::span<Hit>(&hit, 1));
    return hit;
}

bool Crsh::occluded(const Ray& ray) const {
    std::uint8_t o = 0;
    occluded(std::span<const Ray>(&ray, 1), std::span<std::uint8_t>(&o, 1));
    return o != 0;
}

void Crsh::intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options) const {
    check_query("Crsh::intersect", rays.size(), hits.size(), options);
    std::fill(hits.begin(), hits.end(), Hit{});
    trace<false>(*impl_, settings_, rays, hits.data(), nullptr, options);
}

void Crsh::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded, const QueryOptions& options) const {
    check_query("Crsh::occluded", rays.size(), occluded.size(), options);
    std::fill(occluded.begin(), occluded.end(), std::uint8_t{0});
    trace<true>(*impl_, settings_, rays, nullptr, occluded.data(), options);
}

void Crsh::intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                     const QueryOptions& options) const {
    check_query("Crsh::intersect", packets.size(), hits.size(), options);
    const std::vector<Ray> rays = lanes_as_rays(packets);
    std::vector<Hit> answers(rays.size());
    trace<false>(*impl_, settings_, rays, answers.data(), nullptr, options);
    for (std::size_t p = 0; p < packets.size(); ++p)
        for (int i = 0; i < 16; ++i) hits[p].set_hit(i, answers[p * 16 + std::size_t(i)]);
}

void Crsh::occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                    const QueryOptions& options) const {
    check_query("Crsh::occluded", packets.size(), occluded.size(), options);
    const std::vector<Ray> rays = lanes_as_rays(packets);
    std::vector<std::uint8_t> answers(rays.size(), 0);
    trace<true>(*impl_, settings_, rays, nullptr, answers.data(), options);
    for (std::size_t p = 0; p < packets.size(); ++p) {
        std::uint32_t bits = 0;
        for (int i = 0; i < 16; ++i)
            if (answers[p * 16 + std::size_t(i)]) bits |= 1u << i;
        occluded[p] = bits;
    }
}

}  // namespace beamtrace
