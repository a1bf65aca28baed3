// The stream tracer (beamtrace/stream.hpp): keys, sort, groups, then each group traced by what
// suits it, the answers written back in input order.
#include "beamtrace/stream.hpp"

#include <chrono>
#include <optional>
#include <string>

#include "beamtrace/error.hpp"
#include "bvh/wide_bvh.hpp"
#include "common/access.hpp"
#include "common/query_runner.hpp"
#include "kdtree/kd_node.hpp"
#include "stream/group_trace.hpp"
#include "stream/sorted_stream.hpp"
#include "stream/wide_bvh_use.hpp"

namespace beamtrace {

void StreamSettings::validate() const {
    if (!(shared_point_fraction > 0.0f && shared_point_fraction <= 1.0f))
        throw Error("StreamSettings: shared_point_fraction must be in (0, 1], not " +
                    std::to_string(shared_point_fraction));
    if (sample_rays < 0)
        throw Error("StreamSettings: sample_rays must be at least 0, not " + std::to_string(sample_rays));
    if (min_group_rays < 2 || min_group_rays > 16)
        throw Error("StreamSettings: min_group_rays must be in [2, 16], not " + std::to_string(min_group_rays));
}

StreamTracer::StreamTracer(const KdTree& tree, const StreamSettings& settings) : tree_(tree), settings_(settings) {
    settings_.validate();
    if (settings_.wide_bvh) {
        bvh_ = bvh::WideBvh::build(tree_.scene());
        bvh_kernels_ = &bvh::wide_bvh_kernels(detail::Access::impl(tree_).kernels->isa);
    }
}

std::size_t StreamTracer::wide_bvh_bytes() const { return bvh_ ? bvh_->stats.memory_bytes : 0; }
double StreamTracer::wide_bvh_build_seconds() const { return bvh_ ? bvh_->stats.build_seconds : 0.0; }

namespace {

using stream::in_arena;
using stream::RayGroup;
using stream::sort_stream;
using stream::SortedStream;
using stream::StreamTrace;
using stream::WideBvhUse;
constexpr std::size_t kGroupGrain = 256;

template <bool kOcclusion, class Out>
void trace_stream(const KdTree& tree, const StreamSettings& s, WideBvhUse wide_bvh, std::span<const Ray> rays, Out* out,
                  const QueryOptions& options) {
    if (!s.sort && wide_bvh.bvh) {
        wide_bvh.trace_all<kOcclusion>(
            rays.size(), options, [&](std::size_t k) -> const Ray& { return rays[k]; }, out);
        if (options.counters) options.counters->stream.rays += rays.size();
        return;
    }
    if (!s.sort) {
        if constexpr (kOcclusion)
            tree.occluded(rays, std::span<std::uint8_t>(out, rays.size()), options);
        else
            tree.intersect(rays, std::span<Hit>(out, rays.size()), options);
        if (options.counters) options.counters->stream.rays += rays.size();
        return;
    }
    const KdTree::Impl& kd = detail::Access::impl(tree);
    const auto start = std::chrono::steady_clock::now();
    // The calling thread's buffers, kept from call to call (no fresh pages per call); a call made
    // while they are in use on this thread (from a task run during another call) gets its own.
    static thread_local SortedStream kept;
    static thread_local bool kept_in_use = false;
    std::optional<SortedStream> own;
    const bool use_kept = !kept_in_use;
    SortedStream& sorted = use_kept ? kept : own.emplace();
    if (use_kept) kept_in_use = true;
    struct Release {
        bool on;
        ~Release() {
            if (on) kept_in_use = false;
        }
    } release{use_kept};
    const bool bucketed =
        sort_stream(kd.scene.bounds(), s, rays, kOcclusion, wide_bvh.bvh != nullptr, options, kd.kernels->isa, sorted);
    const auto sorted_at = std::chrono::steady_clock::now();
    Out* by_position;
    if constexpr (kOcclusion) {
        sorted.occluded.resize(rays.size());
        by_position = sorted.occluded.data();
    } else {
        sorted.hits.resize(rays.size());
        by_position = sorted.hits.data();
    }
    // The answers from sorted position k to input index index(k).
    const auto scatter = [&](const auto& index) {
        run_query_parts(rays.size(), options, [&](std::size_t b, std::size_t e) {
            for (std::size_t k = b; k < e; ++k) out[index(k)] = by_position[k];
        });
    };
    const std::uint32_t* order = sorted.order.data();
    const auto by_order = [order](std::size_t k) { return order[k]; };
    if (bucketed) {
        // Every ray alone through the wide BVH in the bucket pass's order: read from the records where
        // it left them (beyond the caches; the input index is a word's low half), else from the rays
        // it wrote in order.
        if (options.counters) options.counters->stream.single_rays += rays.size();
        if (sorted.in_records) {
            const stream::SortRecord* records = sorted.sort_buffers.records.data();
            wide_bvh.trace_all<kOcclusion>(
                rays.size(), options, [records](std::size_t k) -> const Ray& { return records[k].ray; }, by_position);
            // Gathered back to input order: sequential stores, random reads (which overlap; a
            // scatter's random stores each read their line first).
            const std::uint32_t* positions = sorted.sort_buffers.positions.data();
            run_query_parts(rays.size(), options, [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i) out[i] = by_position[positions[i]];
            });
        } else {
            const Ray* in_order = sorted.rays.data();
            wide_bvh.trace_all<kOcclusion>(
                rays.size(), options, [in_order](std::size_t k) -> const Ray& { return in_order[k]; }, by_position);
            scatter(by_order);
        }
    } else {
        const StreamTrace<kOcclusion, Out> trace(kd, tree.experimental(), sorted, std::uint32_t(s.min_group_rays),
                                                 s.group_loose_rays, s.bvh_pencils, wide_bvh, by_position);
        run_query(sorted.groups.size(), options, kGroupGrain, [&](std::size_t b, std::size_t e, QueryCounters* c) {
            if (c)
                trace.template groups<true>(b, e, c);
            else
                trace.template groups<false>(b, e, nullptr);
        });
        scatter(by_order);
    }
    if (options.counters) {
        options.counters->stream.rays += rays.size();
        if (bucketed) options.counters->stream.bucket_ordered_rays += rays.size();
        options.counters->stream.sort_nanoseconds +=
            std::uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(sorted_at - start).count());
    }
}

}  // namespace

Hit StreamTracer::intersect(const Ray& ray) const {
    return bvh_ ? bvh_kernels_->intersect(*bvh_, ray) : tree_.intersect(ray);
}
bool StreamTracer::occluded(const Ray& ray) const {
    return bvh_ ? bvh_kernels_->occluded(*bvh_, ray).hit() : tree_.occluded(ray);
}

void StreamTracer::intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options) const {
    check_query("StreamTracer::intersect", rays.size(), hits.size(), options);
    trace_stream<false>(tree_, settings_, WideBvhUse{bvh_.get(), bvh_kernels_}, rays, hits.data(), options);
}

void StreamTracer::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                            const QueryOptions& options) const {
    check_query("StreamTracer::occluded", rays.size(), occluded.size(), options);
    trace_stream<true>(tree_, settings_, WideBvhUse{bvh_.get(), bvh_kernels_}, rays, occluded.data(), options);
}

void StreamTracer::intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                             const QueryOptions& options) const {
    tree_.intersect(packets, hits, options);
}

void StreamTracer::occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                            const QueryOptions& options) const {
    tree_.occluded(packets, occluded, options);
}

void stream_order(std::span<const Ray> rays, const Box& scene_bounds, bool closest_hit, std::span<std::uint32_t> order,
                  const StreamSettings& settings, const QueryOptions& options) {
    check_query("stream_order", rays.size(), order.size(), options);
    settings.validate();
    if (!settings.sort) {
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = std::uint32_t(i);
        return;
    }
    SortedStream sorted;
    sort_stream(scene_bounds, settings, rays, !closest_hit, settings.wide_bvh, options, best_isa(), sorted);
    if (sorted.in_records) {
        const stream::SortRecord* records = sorted.sort_buffers.records.data();
        for (std::size_t k = 0; k < order.size(); ++k) order[k] = std::uint32_t(records[k].word);
        return;
    }
    std::copy(sorted.order.begin(), sorted.order.end(), order.begin());
}

}  // namespace beamtrace
