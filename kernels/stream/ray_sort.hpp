#pragma once
// The stream tracer's sort and gather in one (docs/streams.md, "Sorting the rays themselves"): the
// rays are moved with their sort words instead of being gathered by index afterwards. One pass reads
// the stream in its own order and scatters (ray, word) records by the words' top varying digit into
// buckets; each bucket, small enough for the core's cache, is sorted there by the rest of its words
// and written out: the rays, the order and the sorted keys, each in sorted order. The random reads
// of a gather over the whole stream (a TLB and a cache miss per ray once the stream is larger than
// the caches) become reads within one bucket.
//
// The result is sort_by_key's order and gather_in_order's rays, bit for bit (radix_sort.hpp).
#include <cstdint>
#include <span>
#include <vector>

#include "beamtrace/ray.hpp"
#include "common/huge_page_allocator.hpp"

namespace beamtrace::stream {

// A ray with its sort word (radix_sort.cpp's layout: key, origin-hash bits, index).
struct SortRecord {
    Ray ray;
    std::uint64_t word;
};
static_assert(sizeof(SortRecord) == 40);

// Eight records: five whole cache lines. The scatter of a large stream collects each bucket's next
// eight records in one of these (in cache) and writes them out with streaming stores once all eight
// are there, so that no line of the records is read before it is overwritten.
struct alignas(64) RecordLine {
    SortRecord records[8];
};
static_assert(sizeof(RecordLine) == 5 * 64);

// The records and the scatter's staging lines (per part, one per bucket), kept by the caller across
// calls (no fresh pages per call).
struct RaySortBuffers {
    std::vector<SortRecord, HugePageAllocator<SortRecord>> records;
    // bucket_records: the position of each input ray's record (input index -> position), written in
    // input order as the scatter places the records.
    std::vector<std::uint32_t, HugePageAllocator<std::uint32_t>> positions;
    std::vector<std::vector<RecordLine, HugePageAllocator<RecordLine>>> staging;
};

// order, sorted_keys and sorted_rays as sort_by_key(keys, hashes, order, sorted_keys) and
// gather_in_order(rays, order, 0, n, sorted_rays) give them; every span holds rays.size() (else
// beamtrace::Error). On `parts` threads of the caller's TBB arena.
void sort_rays(std::span<const Ray> rays, std::span<const std::uint32_t> keys, std::span<const std::uint32_t> hashes,
               std::span<std::uint32_t> order, std::span<std::uint32_t> sorted_keys, std::span<Ray> sorted_rays,
               int parts, RaySortBuffers& buffers);

// A stream ordered by the top digit alone (bucket_rays, bucket_records) takes at most 12 bits:
// room's diffuse bounces through the wide BVH alternated with 14 and 10 bits: 5.50, 5.55 / 5.43,
// 5.34 / 5.40, 5.31 Mrays/s; its AO rays the same speed with 12 as with 14 and a smaller sort share
// (14.1, 13.9 % against 15.0, 15.5 %): fewer staging lines for the scatter.
constexpr int kMaxBucketOrderBits = 12;

// The first pass of sort_rays alone (no hashes): the rays by the top digit of their keys (the
// highest up to 12 bits the keys vary in), in input order within a digit: an order by key that is
// exact only to that digit, for rays traced one by one, whose traversal gains from neighbours in
// space, not from an exact order (docs/streams.md, "Streams without shared points in buckets").
// order, sorted_keys and sorted_rays as sort_rays gives them for this order, written straight to
// their places (for streams in the caches; beyond them bucket_records moves fewer bytes).
void bucket_rays(std::span<const Ray> rays, std::span<const std::uint32_t> keys, std::span<std::uint32_t> order,
                 std::span<std::uint32_t> sorted_keys, std::span<Ray> sorted_rays, int parts, RaySortBuffers& buffers);

// bucket_rays' order as records in buffers.records (each ray with its word: key << 32 | input
// index), for a caller that reads the rays where they lie (no copy into sorted arrays); and in
// buffers.positions, where each input ray's record lies (for answers gathered back to input order:
// sequential stores, the random accesses reads).
std::span<const SortRecord> bucket_records(std::span<const Ray> rays, std::span<const std::uint32_t> keys, int parts,
                                           RaySortBuffers& buffers);

}  // namespace beamtrace::stream
