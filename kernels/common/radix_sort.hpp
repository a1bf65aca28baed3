#pragma once
// The library's one radix sort: stable, least significant digit first, 11-bit digits, a pass whose
// digit every record shares skipped, histograms and scatters by part on `parts` threads of the
// caller's TBB arena. The stream tracer sorts (key, index) words with it, CRSH (key, ray) pairs.
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <tbb/parallel_for.h>

namespace beamtrace {

// The bits of a float as an unsigned key in the order of the values (positive ones above negative
// ones, negative ones reversed); -0 is taken as +0, as the float compares do. Not for NaN.
inline std::uint32_t sortable_bits(float x) {
    const std::uint32_t b = std::bit_cast<std::uint32_t>(x + 0.0f);
    return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
}

// Sorts `records` by the low `key_bits` bits of key(record) (a std::uint64_t); equal keys keep their
// order. `scratch` is resized to the records' size (reused across calls).
template <class Record, class KeyOf>
void radix_sort(std::vector<Record>& records, std::vector<Record>& scratch, int key_bits, KeyOf key, int parts) {
    constexpr int kDigitBits = 11, kBuckets = 1 << kDigitBits;
    const std::size_t n = records.size();
    if (n < 2) return;
    parts = std::max(1, std::min(parts, int(n / 65536) + 1));
    const auto for_parts = [&](auto&& f) {
        if (parts == 1) return f(0, std::size_t{0}, n);
        tbb::parallel_for(0, parts, [&](int p) {
            f(p, n * std::size_t(p) / std::size_t(parts), n * std::size_t(p + 1) / std::size_t(parts));
        });
    };
    // Which bits vary: a pass over records that all share its digit changes nothing.
    std::uint64_t all_and = ~std::uint64_t{0}, all_or = 0;
    for (const Record& r : records) {
        all_and &= key(r);
        all_or |= key(r);
    }
    const std::uint64_t varying = all_and ^ all_or;
    scratch.resize(n);
    std::vector<std::array<std::size_t, kBuckets>> count(static_cast<std::size_t>(parts));
    for (int shift = 0; shift < key_bits; shift += kDigitBits) {
        if (((varying >> shift) & (kBuckets - 1)) == 0) continue;
        const auto digit = [&](const Record& r) { return std::size_t((key(r) >> shift) & (kBuckets - 1)); };
        for_parts([&](int p, std::size_t begin, std::size_t end) {
            auto& c = count[std::size_t(p)];
            c.fill(0);
            for (std::size_t i = begin; i < end; ++i) ++c[digit(records[i])];
        });
        // Offsets: bucket by bucket, part by part (stable).
        std::size_t sum = 0;
        for (std::size_t d = 0; d < std::size_t(kBuckets); ++d)
            for (auto& c : count) {
                const std::size_t k = c[d];
                c[d] = sum;
                sum += k;
            }
        for_parts([&](int p, std::size_t begin, std::size_t end) {
            auto& at = count[std::size_t(p)];
            for (std::size_t i = begin; i < end; ++i) scratch[at[digit(records[i])]++] = records[i];
        });
        records.swap(scratch);
    }
}

}  // namespace beamtrace
