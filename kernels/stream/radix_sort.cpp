// Radix sort of the stream tracer's keys (radix_sort.hpp): (key, origin hash, index) in one 64-bit
// word, sorted by key and hash by the library's radix sort (common/radix_sort.hpp).
#include "stream/radix_sort.hpp"

#include <algorithm>
#include <cstdint>

#include <immintrin.h>

#include "common/radix_sort.hpp"
#include "stream/ray_keys.hpp"

namespace beamtrace::stream {

SortWords::SortWords(std::span<const std::uint32_t> keys, std::span<const std::uint32_t> hashes) {
    // Hash bits only when some ray is keyed by its origin's cell (a stream of pencils sorts by key).
    const bool by_origin =
        !hashes.empty() && std::any_of(keys.begin(), keys.end(), [](std::uint32_t k) { return (k & kPencilBit) == 0; });
    hash_bits = by_origin ? stream::hash_bits(keys.size()) : 0;
    index_bits = 32 - hash_bits;
    index_mask = (std::uint64_t{1} << index_bits) - 1;
}

void sort_by_key(std::span<const std::uint32_t> keys, std::span<const std::uint32_t> hashes,
                 std::span<std::uint32_t> order, std::span<std::uint32_t> sorted_keys, int parts,
                 SortBuffers& buffers) {
    const std::size_t n = keys.size();
    const SortWords layout(keys, hashes);
    auto& records = buffers.records;
    records.resize(n);
    for (std::size_t i = 0; i < n; ++i) records[i] = layout.word(keys[i], layout.hash_bits ? hashes[i] : 0, i);
    radix_sort(
        records, buffers.scratch, 32 + layout.hash_bits,
        [index_bits = layout.index_bits](std::uint64_t r) { return r >> index_bits; }, parts);
    // Unpacked in a pass of its own: a last scatter writing the order and the keys apart would keep
    // twice the destinations open (measured slower).
    for (std::size_t k = 0; k < n; ++k) {
        order[k] = layout.index(records[k]);
        sorted_keys[k] = SortWords::key(records[k]);
    }
}

void gather_in_order(std::span<const Ray> rays, std::span<const std::uint32_t> order, std::size_t begin,
                     std::size_t end, std::span<Ray> out) {
    // Streams of up to a million rays (32 MB) may stay in cache for the trace: plain stores.
    const bool streaming = rays.size() >= kStreamingRays && reinterpret_cast<std::uintptr_t>(out.data()) % 16 == 0;
    for (std::size_t k = begin; k < end; ++k) {
        if (k + kGatherAhead < end) __builtin_prefetch(&rays[order[k + kGatherAhead]]);
        store_ray(&out[k], rays[order[k]], streaming);
    }
    if (streaming) _mm_sfence();  // the streamed lines are seen by whichever thread reads them next
}

}  // namespace beamtrace::stream
