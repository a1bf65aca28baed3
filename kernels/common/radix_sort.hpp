#pragma once
// The library's one radix sort: stable, least significant digit first, digits of at most 11 bits.
// One pass counts every digit's histogram (and so finds the digits every record shares: their passes
// are skipped). Histograms and scatters by part on `parts` threads of the caller's TBB arena. The stream
// tracer sorts (key, index) words with it, CRSH (key, ray) pairs, the kd build split events.
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <tbb/parallel_for.h>

namespace beamtrace {

// The bits of a float as an unsigned key in the order of the values (positive ones above negative
// ones, negative ones reversed); -0 is taken as +0, as the float compares do. Not for NaN.
inline std::uint32_t sortable_bits(float x) {
    const std::uint32_t b = std::bit_cast<std::uint32_t>(x + 0.0f);
    return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
}

namespace radix_detail {

inline constexpr int kDigitBits = 11, kBuckets = 1 << kDigitBits, kMaxDigits = (64 + kDigitBits - 1) / kDigitBits;
using Histogram = std::array<std::uint32_t, kBuckets>;

}  // namespace radix_detail

// Sorts `records` by the low `key_bits` bits of key(record) (a std::uint64_t); equal keys keep their
// order. `scratch` is resized to the records' size (reused across calls).
template <class Record, class KeyOf>
void radix_sort(std::vector<Record>& records, std::vector<Record>& scratch, int key_bits, KeyOf key, int parts) {
    using namespace radix_detail;
    const std::size_t n = records.size();
    if (n < 2) return;
    if (n > std::size_t(0xFFFFFFFFu)) {  // beyond the histograms' 32-bit counts
        const std::uint64_t mask = key_bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << key_bits) - 1;
        std::stable_sort(records.begin(), records.end(),
                         [&](const Record& a, const Record& b) { return (key(a) & mask) < (key(b) & mask); });
        return;
    }
    parts = std::max(1, std::min(parts, int(n / 65536) + 1));
    key_bits = std::clamp(key_bits, 0, 64);
    // Digits of near-equal width, at most kDigitBits each: 13 key bits take two 7-bit digits (128
    // buckets to clear and add up per pass), not 11 + 2 (2,048 each), which matters for small inputs.
    const int digits = std::min(kMaxDigits, (key_bits + kDigitBits - 1) / kDigitBits);
    const int width = digits == 0 ? kDigitBits : (key_bits + digits - 1) / digits;
    const std::size_t buckets = std::size_t{1} << std::min(width, kDigitBits);
    const std::uint64_t digit_mask = buckets - 1;
    const auto range = [&](int p) {
        return std::pair{n * std::size_t(p) / std::size_t(parts), n * std::size_t(p + 1) / std::size_t(parts)};
    };
    const auto for_parts = [&](auto&& f) {
        if (parts == 1) return f(0);
        tbb::parallel_for(0, parts, [&](int p) { f(p); });
    };
    // count[p][j]: part p's histogram of digit j; every digit counted in one pass over the input.
    // Left uninitialised (a digit's histogram is cleared before it is counted): the stream sort calls
    // this for thousands of small buckets, and zeroing 48 KB each time would cost more than sorting.
    const std::unique_ptr<std::array<Histogram, kMaxDigits>[]> count(
        new std::array<Histogram, kMaxDigits>[static_cast<std::size_t>(parts)]);
    for_parts([&](int p) {
        auto& c = count[std::size_t(p)];
        for (int j = 0; j < digits; ++j) std::fill_n(c[std::size_t(j)].begin(), buckets, 0u);
        const auto [begin, end] = range(p);
        for (std::size_t i = begin; i < end; ++i) {
            const std::uint64_t k = key(records[i]);
            for (int j = 0; j < digits; ++j) ++c[std::size_t(j)][(k >> (j * width)) & digit_mask];
        }
    });
    scratch.resize(n);
    const std::unique_ptr<std::array<std::size_t, kBuckets>[]> at(
        new std::array<std::size_t, kBuckets>[static_cast<std::size_t>(parts)]);
    bool counted = true;  // count[.][j] holds the parts' records as they are now
    for (int j = 0; j < digits; ++j) {
        const int shift = j * width;
        const auto digit = [&](const Record& r) { return std::size_t((key(r) >> shift) & digit_mask); };
        // A digit whose one bucket holds every record changes nothing: its pass is skipped. (No pass
        // moves a record to another bucket of a digit all records share: the first record's tells.)
        std::size_t first_bucket = 0;
        for (int p = 0; p < parts; ++p) first_bucket += count[std::size_t(p)][std::size_t(j)][digit(records[0])];
        if (first_bucket == n) continue;
        if (!counted)  // the parts hold other records now: count them again
            for_parts([&](int p) {
                Histogram& c = count[std::size_t(p)][std::size_t(j)];
                std::fill_n(c.begin(), buckets, 0u);
                const auto [begin, end] = range(p);
                for (std::size_t i = begin; i < end; ++i) ++c[digit(records[i])];
            });
        // Offsets: bucket by bucket, part by part (stable).
        std::size_t sum = 0;
        for (std::size_t d = 0; d < buckets; ++d)
            for (std::size_t p = 0; p < std::size_t(parts); ++p) {
                at[p][d] = sum;
                sum += count[p][std::size_t(j)][d];
            }
        for_parts([&](int p) {
            auto& to = at[std::size_t(p)];
            const auto [begin, end] = range(p);
            for (std::size_t i = begin; i < end; ++i) scratch[to[digit(records[i])]++] = records[i];
        });
        records.swap(scratch);
        counted = parts == 1;  // one part: the whole input, whose histograms no pass changes
    }
}

}  // namespace beamtrace
