#pragma once
// The sorting step of the stream tracer: 32-bit keys with their indices sorted by the library's
// radix sort (common/radix_sort.hpp: stable, 11-bit digits, passes whose digit all keys share
// skipped, on `parts` threads of the caller's TBB arena), in linear time; then the rays gathered
// into that order.
#include <cstdint>
#include <span>
#include <vector>

#include "beamtrace/ray.hpp"

namespace beamtrace::stream {

// The sort's (key, index) words and its scratch, kept by the caller across calls.
struct SortBuffers {
    std::vector<std::uint64_t> records, scratch;
};

// Fills `order` with 0 .. keys.size()-1 sorted by key (equal keys keep their input order) and
// sorted_keys[k] with keys[order[k]].
void sort_by_key(std::span<const std::uint32_t> keys, std::span<std::uint32_t> order,
                 std::span<std::uint32_t> sorted_keys, int parts, SortBuffers& buffers);

// out[k] = rays[order[k]] for k in [begin, end): the rays in sorted order. The reads are random
// over the whole stream, so each is asked for `kGatherAhead` rays before it is copied (their misses
// overlap).
inline constexpr std::size_t kGatherAhead = 16;
void gather_in_order(std::span<const Ray> rays, std::span<const std::uint32_t> order, std::size_t begin,
                     std::size_t end, std::span<Ray> out);

}  // namespace beamtrace::stream
