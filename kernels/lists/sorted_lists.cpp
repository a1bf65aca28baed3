// The SortedLists object and its query contract (query.hpp): every ray alone through
// lists::trace_ray; spans on TBB threads; packets lane by lane.
#include "beamtrace/sorted_lists.hpp"

#include <chrono>
#include <string>

#include "beamtrace/error.hpp"
#include "common/query_runner.hpp"
#include "lists/list_traversal.hpp"

namespace beamtrace {

namespace {

constexpr std::size_t kRayGrain = 256, kPacketGrain = 16;

template <bool kOcclusion>
Hit trace(const SortedLists::Impl& impl, const Ray& ray, QueryCounters* c) {
    return c ? lists::trace_ray<kOcclusion, true>(impl, ray, c)
             : lists::trace_ray<kOcclusion, false>(impl, ray, nullptr);
}

template <bool kOcclusion, class Out>
void trace_rays(const SortedLists::Impl& impl, std::span<const Ray> rays, Out* out, const QueryOptions& options) {
    run_query(rays.size(), options, kRayGrain, [&](std::size_t b, std::size_t e, QueryCounters* c) {
        for (std::size_t i = b; i < e; ++i) {
            const Hit h = trace<kOcclusion>(impl, rays[i], c);
            if constexpr (kOcclusion)
                out[i] = h.hit();
            else
                out[i] = h;
        }
    });
}

// Packets lane by lane; inactive lanes report no hit.
template <bool kOcclusion>
void trace_packets(const SortedLists::Impl& impl, std::span<const Packet16> packets, PacketHits16* hits,
                   std::uint32_t* bits, const QueryOptions& options) {
    run_query(packets.size(), options, kPacketGrain, [&](std::size_t b, std::size_t e, QueryCounters* c) {
        for (std::size_t p = b; p < e; ++p) {
            std::uint32_t occluded = 0;
            for (int i = 0; i < 16; ++i) {
                const bool active = (packets[p].active >> i) & 1u;
                const Hit h = active ? trace<kOcclusion>(impl, packets[p].ray(i), c) : Hit{};
                if constexpr (kOcclusion) {
                    if (h.hit()) occluded |= 1u << i;
                } else {
                    hits[p].set_hit(i, h);
                }
            }
            if constexpr (kOcclusion) bits[p] = occluded;
        }
    });
}

}  // namespace

void SortedListRules::validate() const {
    for (int a = 0; a < 3; ++a)
        if (grid[a] < 1 || grid[a] > 16)
            throw Error("SortedListRules: grid[" + std::to_string(a) + "] must be between 1 and 16, not " +
                        std::to_string(grid[a]));
    if (!flat && grid[0] * grid[1] * grid[2] < 2)
        throw Error(
            "SortedListRules: the grid must have at least 2 cells (1x1x1 never splits; use flat for one level)");
    if (leaf_objects < 1)
        throw Error("SortedListRules: leaf_objects must be at least 1, not " + std::to_string(leaf_objects));
    if (!(special_cell_fraction > 0.0f && special_cell_fraction <= 1.0f))
        throw Error("SortedListRules: special_cell_fraction must be in (0, 1], not " +
                    std::to_string(special_cell_fraction));
}

SortedLists SortedLists::build(const Scene& scene, const SortedListRules& rules) {
    rules.validate();
    if (scene.triangle_count() >= std::size_t{1} << 31) throw Error("SortedLists: at most 2^31 - 1 triangles");
    const auto start = std::chrono::steady_clock::now();
    auto impl = std::make_shared<Impl>(scene, rules);
    lists::build_hierarchy(*impl);
    impl->stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return SortedLists(std::move(impl));
}

const Scene& SortedLists::scene() const { return impl_->scene; }
const SortedListRules& SortedLists::rules() const { return impl_->rules; }
const SortedListStats& SortedLists::stats() const { return impl_->stats; }

Hit SortedLists::intersect(const Ray& ray) const { return lists::trace_ray<false, false>(*impl_, ray, nullptr); }
bool SortedLists::occluded(const Ray& ray) const { return lists::trace_ray<true, false>(*impl_, ray, nullptr).hit(); }

void SortedLists::intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options) const {
    check_query("SortedLists::intersect", rays.size(), hits.size(), options);
    trace_rays<false>(*impl_, rays, hits.data(), options);
}

void SortedLists::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                           const QueryOptions& options) const {
    check_query("SortedLists::occluded", rays.size(), occluded.size(), options);
    trace_rays<true>(*impl_, rays, occluded.data(), options);
}

void SortedLists::intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                            const QueryOptions& options) const {
    check_query("SortedLists::intersect", packets.size(), hits.size(), options);
    trace_packets<false>(*impl_, packets, hits.data(), nullptr, options);
}

void SortedLists::occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                           const QueryOptions& options) const {
    check_query("SortedLists::occluded", packets.size(), occluded.size(), options);
    trace_packets<true>(*impl_, packets, nullptr, occluded.data(), options);
}

}  // namespace beamtrace
