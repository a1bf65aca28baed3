#pragma once
// The ordering of a stream tracer call (docs/streams.md, steps 1-5): shared points, keys, the sort
// (or the bucket pass alone) and the groups, into buffers the calling thread keeps from call to call.
#include <cstdint>
#include <span>
#include <vector>

#include <tbb/task_arena.h>

#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "beamtrace/stream.hpp"
#include "common/huge_page_allocator.hpp"
#include "simd/isa.hpp"
#include "stream/ray_groups.hpp"
#include "stream/ray_sort.hpp"

namespace beamtrace::stream {

// The sorted order of a call: keys, order, the rays in that order, and groups.
struct SortedStream {
    // bucket_records: the order is in sort_buffers.records (the rays where the scatter put them, each
    // with its input index) and sort_buffers.positions (where each input ray went), not in order and
    // rays.
    bool in_records = false;
    std::vector<std::uint32_t> keys, hashes, order, sorted_keys;
    std::vector<Ray, HugePageAllocator<Ray>> rays;  // in sorted order (huge pages: common/huge_page_allocator.hpp)
    RaySortBuffers sort_buffers;
    std::vector<RayGroup> groups;
    // The answers by sorted position, written to the caller's spans in input order at the end of the
    // call: written there directly, ray by ray between walks, the scattered stores evicted the
    // trees' lines from the caches (docs/streams.md, "Answers in sorted order").
    std::vector<Hit, HugePageAllocator<Hit>> hits;
    std::vector<std::uint8_t, HugePageAllocator<std::uint8_t>> occluded;
};

// Runs f in an arena of `threads` threads (on the calling thread when 1).
template <class F>
void in_arena(int threads, F&& f) {
    if (threads <= 1) {
        f();
        return;
    }
    tbb::task_arena arena(threads);
    arena.execute(f);
}

// Keys, sort, gather and groups of a call's rays into `out` (the calling thread's buffers). With
// `buckets_suffice` (rays traced alone go through the wide BVH) a stream whose sample shows no shared
// point is ordered by the bucket pass alone, every ray a single; returns whether it was.
bool sort_stream(const Box& bounds, const StreamSettings& s, std::span<const Ray> rays, bool occlusion,
                 bool buckets_suffice, const QueryOptions& options, Isa isa, SortedStream& out);

}  // namespace beamtrace::stream
