// Radix sort of the stream tracer's keys (radix_sort.hpp).
#include "stream/radix_sort.hpp"

#include <algorithm>
#include <array>

#include <tbb/parallel_for.h>

namespace beamtrace::stream {

namespace {

constexpr int kDigitBits = 11, kBuckets = 1 << kDigitBits, kPasses = 3;

// f(part, begin, end) for `parts` contiguous parts of [0, n), in parallel (in the caller's arena).
template <class F>
void for_parts(std::size_t n, int parts, F&& f) {
    if (parts <= 1) {
        f(0, std::size_t{0}, n);
        return;
    }
    tbb::parallel_for(0, parts, [&](int p) { f(p, n * std::size_t(p) / std::size_t(parts), n * std::size_t(p + 1) / std::size_t(parts)); });
}

}  // namespace

void sort_by_key(std::span<const std::uint32_t> keys, std::span<std::uint32_t> order,
                 std::span<std::uint32_t> sorted_keys, int parts, std::vector<std::uint64_t>& scratch) {
    const std::size_t n = keys.size();
    parts = std::max(1, std::min(parts, int(n / 65536) + 1));
    scratch.resize(2 * n);
    std::uint64_t* a = scratch.data();
    std::uint64_t* b = scratch.data() + n;
    // Which digits vary: a pass over keys that all share a digit changes nothing.
    std::uint32_t all_and = 0xFFFFFFFFu, all_or = 0;
    for_parts(n, 1, [&](int, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            a[i] = (std::uint64_t(keys[i]) << 32) | i;
            all_and &= keys[i];
            all_or |= keys[i];
        }
    });
    const std::uint32_t varying = all_and ^ all_or;
    std::vector<std::array<std::size_t, kBuckets>> count(static_cast<std::size_t>(parts));
    for (int pass = 0; pass < kPasses; ++pass) {
        const int shift = 32 + pass * kDigitBits;
        if (((varying >> (shift - 32)) & (kBuckets - 1)) == 0) continue;
        for_parts(n, parts, [&](int p, std::size_t begin, std::size_t end) {
            auto& c = count[std::size_t(p)];
            c.fill(0);
            for (std::size_t i = begin; i < end; ++i) ++c[(a[i] >> shift) & (kBuckets - 1)];
        });
        // Offsets: bucket by bucket, part by part (stable).
        std::size_t sum = 0;
        for (int d = 0; d < kBuckets; ++d)
            for (int p = 0; p < parts; ++p) {
                const std::size_t c = count[std::size_t(p)][std::size_t(d)];
                count[std::size_t(p)][std::size_t(d)] = sum;
                sum += c;
            }
        for_parts(n, parts, [&](int p, std::size_t begin, std::size_t end) {
            auto& at = count[std::size_t(p)];
            for (std::size_t i = begin; i < end; ++i) b[at[(a[i] >> shift) & (kBuckets - 1)]++] = a[i];
        });
        std::swap(a, b);
    }
    for_parts(n, parts, [&](int, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            order[i] = std::uint32_t(a[i]);
            sorted_keys[i] = std::uint32_t(a[i] >> 32);
        }
    });
}

}  // namespace beamtrace::stream
