// The ordering of a stream tracer call (sorted_stream.hpp).
#include "stream/sorted_stream.hpp"

#include <string>

#include "beamtrace/error.hpp"
#include "common/query_runner.hpp"
#include "stream/radix_sort.hpp"
#include "stream/ray_keys.hpp"

namespace beamtrace::stream {

bool sort_stream(const Box& bounds, const StreamSettings& s, std::span<const Ray> rays, bool occlusion,
                 bool buckets_suffice, const QueryOptions& options, Isa isa, SortedStream& out) {
    if (rays.size() > std::size_t(0xFFFFFFFFu))
        throw Error("StreamTracer: at most 4294967295 rays per call, not " + std::to_string(rays.size()));
    SharedPoints shared =
        find_shared_points(rays, bounds, s.sample_rays, s.shared_point_fraction, StreamSettings::kMaxSharedPoints);
    if (!occlusion) std::erase_if(shared.points, [](const SharedPoint& p) { return p.ends; });
    const bool bucketed = buckets_suffice && s.bucket_order && shared.points.empty();
    // Keys, then the origins' hashes of the rays keyed by cell, a chunk at a time (its rays still in
    // cache). Hashes only for the whole sort, where the sample saw an origin twice: else a cell's
    // rays would gain nothing from them (one ray an origin, or each origin's rays already next to
    // each other).
    const bool hashed = !bucketed && shared.repeated_origins > 0;
    out.keys.resize(rays.size());
    if (!bucketed || rays.size() < kStreamingRays) {
        out.order.resize(rays.size());
        out.sorted_keys.resize(rays.size());
        out.rays.resize(rays.size());
    }
    out.hashes.resize(hashed ? rays.size() : 0);
    constexpr std::size_t kChunk = 4096;
    run_query_parts(rays.size(), options, [&](std::size_t b, std::size_t e) {
        for (std::size_t c = b; c < e; c += kChunk) {
            const std::size_t ce = std::min(e, c + kChunk);
            make_keys(rays.subspan(c, ce - c), bounds, shared, std::span(out.keys).subspan(c, ce - c), isa);
            if (hashed)
                for (std::size_t i = c; i < ce; ++i)
                    out.hashes[i] = (out.keys[i] & kPencilBit) ? 0 : origin_hash(rays[i]);
        }
    });
    // Bucketed: no groups; every ray goes alone through the wide BVH, which answers rays that describe
    // no segment as the no-segment groups do. Beyond the caches the rays stay in the records where
    // the scatter left them (no copy).
    out.groups.clear();
    out.in_records = bucketed && rays.size() >= kStreamingRays;
    if (out.in_records) {
        in_arena(options.threads, [&] { bucket_records(rays, out.keys, options.threads, out.sort_buffers); });
        return true;
    }
    if (bucketed) {
        in_arena(options.threads, [&] {
            bucket_rays(rays, out.keys, out.order, out.sorted_keys, out.rays, options.threads, out.sort_buffers);
        });
        return true;
    }
    // Sorted and gathered in one (stream/ray_sort.hpp: the rays move with their sort words).
    in_arena(options.threads, [&] {
        sort_rays(rays, out.keys, out.hashes, out.order, out.sorted_keys, out.rays, options.threads, out.sort_buffers);
    });
    in_arena(options.threads, [&] { cut_groups(out.sorted_keys, s.min_group_rays, out.groups, options.threads); });
    return false;
}

}  // namespace beamtrace::stream
