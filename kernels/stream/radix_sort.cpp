// Radix sort of the stream tracer's keys (radix_sort.hpp): (key, index) in one 64-bit word, sorted
// by the key by the library's radix sort (common/radix_sort.hpp), whose last pass writes the order
// and the sorted keys.
#include "stream/radix_sort.hpp"

#include "common/radix_sort.hpp"

namespace beamtrace::stream {

void sort_by_key(std::span<const std::uint32_t> keys, std::span<std::uint32_t> order,
                 std::span<std::uint32_t> sorted_keys, int parts, SortBuffers& buffers) {
    const std::size_t n = keys.size();
    auto& records = buffers.records;
    records.resize(n);
    for (std::size_t i = 0; i < n; ++i) records[i] = (std::uint64_t(keys[i]) << 32) | i;
    // The last pass writes the order and the sorted keys themselves (no copy of the records).
    radix_sort_to(records, buffers.scratch, 32, [](std::uint64_t r) { return r >> 32; }, parts,
                  [&](std::size_t to, std::uint64_t r) {
                      order[to] = std::uint32_t(r);
                      sorted_keys[to] = std::uint32_t(r >> 32);
                  });
}

void gather_in_order(std::span<const Ray> rays, std::span<const std::uint32_t> order, std::size_t begin,
                     std::size_t end, std::span<Ray> out) {
    for (std::size_t k = begin; k < end; ++k) {
        if (k + kGatherAhead < end) __builtin_prefetch(&rays[order[k + kGatherAhead]]);
        out[k] = rays[order[k]];
    }
}

}  // namespace beamtrace::stream
