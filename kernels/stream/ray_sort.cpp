// The stream tracer's sort and gather in one (ray_sort.hpp).
#include "stream/ray_sort.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <string>

#include <immintrin.h>
#include <tbb/parallel_for.h>

#include "beamtrace/error.hpp"
#include "common/radix_sort.hpp"
#include "stream/radix_sort.hpp"

namespace beamtrace::stream {

namespace {

// The scatter's digit: up to 14 bits (16,384 buckets; 16 bits filled 4,585 of 65,536 with room's
// 16.8 million AO rays, whose keys crowd where the surfaces are, and kept more staging lines in
// cache than the scatter could afford), fewer for smaller streams (about 256 rays a bucket).
constexpr int kMaxTopBits = 14;
int top_bits(std::size_t n) { return std::clamp(int(std::bit_width(n)) - 8, 1, kMaxTopBits); }
constexpr std::size_t kSmallBucket = 48;  // sorted by std::sort

// The per-thread words of one bucket: (the words' value below the top digit, position in the bucket).
// Kept from bucket to bucket and call to call, up to kKeptWords of them (16 MB): a larger bucket (a
// stream whose keys crowd into one top digit) gets them for its own sort only.
constexpr std::size_t kKeptWords = std::size_t{1} << 20;
struct BucketWords {
    std::vector<std::uint64_t> a, b;
    void trim() {
        if (a.capacity() <= kKeptWords) return;
        a = {};
        b = {};
    }
};

class BucketSort {
public:
    BucketSort(const SortWords& layout, int low_bits, const SortRecord* records, std::span<std::uint32_t> order,
               std::span<std::uint32_t> sorted_keys, std::span<Ray> sorted_rays, bool streaming)
        : layout_(layout),
          low_mask_(low_bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << low_bits) - 1),
          records_(records),
          order_(order),
          sorted_keys_(sorted_keys),
          sorted_rays_(sorted_rays),
          streaming_(streaming) {}

    // Sorts the records [begin, end) (they share the top digit) into the outputs' [begin, end).
    void operator()(std::size_t begin, std::size_t end, BucketWords& words) const {
        const std::size_t m = end - begin;
        const int pos_bits = std::max(1, int(std::bit_width(m - 1)));
        words.a.resize(m);
        std::uint64_t* w = words.a.data();
        std::uint64_t any = 0, all = ~std::uint64_t{0};
        for (std::size_t j = 0; j < m; ++j) {
            const std::uint64_t v = layout_.value(records_[begin + j].word) & low_mask_;
            any |= v;
            all &= v;
            w[j] = (v << pos_bits) | j;  // positions ascend: equal values keep the input order
        }
        const int top = std::bit_width(any ^ all);
        if (top > 0 && m <= kSmallBucket) {
            std::sort(w, w + m);
        } else if (top > 0) {  // by the value bits above the positions (the library's radix sort: stable)
            radix_sort(
                words.a, words.b, top, [pos_bits](std::uint64_t x) { return x >> pos_bits; }, 1);
            w = words.a.data();
        }
        write(w, begin, m, (std::uint64_t{1} << pos_bits) - 1);
        words.trim();
    }

private:
    // The bucket's records in the words' order: rays, indices, keys.
    void write(const std::uint64_t* w, std::size_t begin, std::size_t m, std::uint64_t pos_mask) const {
        const SortRecord* from = records_ + begin;
        Ray* rays = sorted_rays_.data() + begin;
        std::uint32_t* order = order_.data() + begin;
        std::uint32_t* keys = sorted_keys_.data() + begin;
        for (std::size_t k = 0; k < m; ++k) {
            const SortRecord& r = from[w[k] & pos_mask];
            order[k] = layout_.index(r.word);
            keys[k] = SortWords::key(r.word);
            store_ray(rays + k, r.ray, streaming_);
        }
    }

    const SortWords& layout_;
    std::uint64_t low_mask_;
    const SortRecord* records_;
    std::span<std::uint32_t> order_, sorted_keys_;
    std::span<Ray> sorted_rays_;
    bool streaming_;
};

// The rays [begin, end) scattered into records[t[digit]++], by way of one RecordLine per bucket:
// position k of a bucket goes to slot k % 8 of its line, and a line whose eight positions this part
// wrote goes out by streaming stores to records[k - 7 .. k] (line-aligned: records is). Positions
// of lines this part shares with its neighbours (at the ends of its range of a bucket) are copied
// by plain stores.
template <class Word>
void scatter_combined(std::span<const Ray> rays, const Word& word, const SortWords& layout, int shift,
                      std::size_t buckets, std::size_t begin, std::size_t end, std::vector<std::size_t>& t,
                      RecordLine* lines, SortRecord* records, std::uint32_t* positions) {
    const std::vector<std::size_t> first = t;  // this part's first position in each bucket
    const auto copy = [&](std::size_t d, std::size_t from, std::size_t to) {  // plain stores of [from, to)
        for (std::size_t k = from; k < to; ++k) records[k] = lines[d].records[k & 7];
    };
    for (std::size_t i = begin; i < end; ++i) {
        const std::uint64_t w = word(i);
        const std::size_t d = (layout.value(w) >> shift) & (buckets - 1);
        const std::size_t k = t[d]++;
        if (positions) positions[i] = std::uint32_t(k);
        SortRecord& r = lines[d].records[k & 7];
        r.ray = rays[i];
        r.word = w;
        if ((k & 7) != 7) continue;
        if (k - 7 >= first[d]) {
            const auto* from = reinterpret_cast<const __m128i*>(&lines[d]);
            auto* to = reinterpret_cast<__m128i*>(records + (k - 7));
            for (int q = 0; q < int(sizeof(RecordLine) / 16); ++q) _mm_stream_si128(to + q, _mm_load_si128(from + q));
        } else {
            copy(d, first[d], k + 1);
        }
    }
    for (std::size_t d = 0; d < buckets; ++d)
        if (t[d] & 7) copy(d, std::max(first[d], t[d] & ~std::size_t{7}), t[d]);
}

// What order_rays makes: sort_rays' order, bucket_rays' order in sorted arrays, or bucket_rays'
// order left in the records.
enum class Ordering { sorted, buckets, bucket_records };

void order_rays(std::span<const Ray> rays, std::span<const std::uint32_t> keys, std::span<const std::uint32_t> hashes,
                std::span<std::uint32_t> order, std::span<std::uint32_t> sorted_keys, std::span<Ray> sorted_rays,
                int parts, RaySortBuffers& buffers, Ordering ordering, const char* what) {
    const std::size_t n = rays.size();
    const bool arrays = ordering != Ordering::bucket_records;  // else the records are the result
    if (keys.size() != n || (arrays && (order.size() != n || sorted_keys.size() != n || sorted_rays.size() != n)) ||
        (!hashes.empty() && hashes.size() != n))
        throw Error(std::string(what) +
                    ": keys, hashes (when given), order, sorted keys and sorted rays must hold one entry per ray (" +
                    std::to_string(n) + ")");
    if (n > std::size_t(0xFFFFFFFFu))
        throw Error(std::string(what) + ": at most 4294967295 rays, not " + std::to_string(n));
    if (n == 0) return;
    const SortWords layout(keys, hashes);
    const auto word = [&](std::size_t i) { return layout.word(keys[i], layout.hash_bits ? hashes[i] : 0, i); };
    parts = std::max(1, std::min(parts, int(n / 65536) + 1));
    const auto range = [&](int p) {
        return std::pair{n * std::size_t(p) / std::size_t(parts), n * std::size_t(p + 1) / std::size_t(parts)};
    };
    const auto for_parts = [&](auto&& f) {
        if (parts == 1) return f(0);
        tbb::parallel_for(0, parts, [&](int p) { f(p); });
    };
    // The bits the words' values vary in; the top digit is the highest top_bits(n) of them.
    std::vector<std::array<std::uint64_t, 2>> seen(static_cast<std::size_t>(parts));  // (any, all) per part
    // A word's value is (key << hash_bits) | hash bits: the keys' and the hash bits' any and all,
    // each a plain pass over 32-bit words, give the values'.
    for_parts([&](int p) {
        const auto [begin, end] = range(p);
        std::uint32_t any_key = 0, all_key = ~0u, any_hash = 0, all_hash = ~0u;
        for (std::size_t i = begin; i < end; ++i) {
            any_key |= keys[i];
            all_key &= keys[i];
        }
        if (layout.hash_bits) {
            const int drop = 32 - layout.hash_bits;
            for (std::size_t i = begin; i < end; ++i) {
                const std::uint32_t h = (keys[i] & kPencilBit) ? 0u : hashes[i] >> drop;
                any_hash |= h;
                all_hash &= h;
            }
        } else {
            all_hash = 0;
        }
        const int hb = layout.hash_bits;
        seen[std::size_t(p)] = {(std::uint64_t(any_key) << hb) | any_hash,
                                (std::uint64_t(all_key) << hb) | (all_hash & ((std::uint64_t{1} << hb) - 1))};
    });
    std::uint64_t any = 0, all = ~std::uint64_t{0};
    for (const auto& s : seen) any |= s[0], all &= s[1];
    const int top = std::bit_width(any ^ all);
    const int digit_bits = ordering == Ordering::sorted ? top_bits(n) : std::min(top_bits(n), kMaxBucketOrderBits);
    const std::size_t buckets = std::size_t{1} << digit_bits;
    const int shift = std::max(0, top - digit_bits);
    const auto digit = [&](std::size_t i) { return std::size_t((layout.value(word(i)) >> shift) & (buckets - 1)); };
    std::vector<std::vector<std::uint32_t>> count(static_cast<std::size_t>(parts));
    for_parts([&](int p) {
        auto& c = count[std::size_t(p)];
        c.assign(buckets, 0);
        const auto [begin, end] = range(p);
        for (std::size_t i = begin; i < end; ++i) ++c[digit(i)];
    });
    // Offsets: bucket by bucket, part by part (stable).
    std::vector<std::size_t> at(buckets + 1);
    std::vector<std::vector<std::size_t>> to(static_cast<std::size_t>(parts), std::vector<std::size_t>(buckets));
    std::size_t sum = 0;
    for (std::size_t d = 0; d < buckets; ++d) {
        at[d] = sum;
        for (std::size_t p = 0; p < std::size_t(parts); ++p) {
            to[p][d] = sum;
            sum += count[p][d];
        }
    }
    at[buckets] = sum;
    if (ordering == Ordering::buckets) {
        // The rays, indices and keys straight to their places. (Beyond the caches three scattered
        // streams of stores a bucket measured slower than the records' one: the stream tracer takes
        // bucket_records there.)
        for_parts([&](int p) {
            auto& t = to[std::size_t(p)];
            const auto [begin, end] = range(p);
            for (std::size_t i = begin; i < end; ++i) {
                const std::uint64_t w = word(i);
                const std::size_t k = t[(layout.value(w) >> shift) & (buckets - 1)]++;
                sorted_rays[k] = rays[i];
                order[k] = std::uint32_t(i);
                sorted_keys[k] = SortWords::key(w);
            }
        });
        return;
    }
    auto& records = buffers.records;
    records.resize(n);
    // Positions only for bucket_records' callers (the sorted order is in the words).
    std::uint32_t* positions = nullptr;
    if (ordering == Ordering::bucket_records) {
        buffers.positions.resize(n);
        positions = buffers.positions.data();
    }
    // Large streams: records staged eight at a time per bucket (RecordLine), written by streaming
    // stores (the records are far beyond the caches; a plain store reads each line first).
    const bool combine = n >= kStreamingRays && reinterpret_cast<std::uintptr_t>(records.data()) % 64 == 0;
    if (combine) {
        buffers.staging.resize(std::size_t(parts));
        for (auto& lines : buffers.staging)
            if (lines.size() < buckets) lines.resize(buckets);
    }
    for_parts([&](int p) {
        auto& t = to[std::size_t(p)];
        const auto [begin, end] = range(p);
        if (!combine) {
            for (std::size_t i = begin; i < end; ++i) {
                const std::uint64_t w = word(i);
                const std::size_t k = t[(layout.value(w) >> shift) & (buckets - 1)]++;
                if (positions) positions[i] = std::uint32_t(k);
                SortRecord& r = records[k];
                r.ray = rays[i];
                r.word = w;
            }
            return;
        }
        scatter_combined(rays, word, layout, shift, buckets, begin, end, t, buffers.staging[std::size_t(p)].data(),
                         records.data(), positions);
    });
    if (combine) _mm_sfence();
    if (ordering == Ordering::bucket_records) return;
    const bool streaming = n >= kStreamingRays && reinterpret_cast<std::uintptr_t>(sorted_rays.data()) % 16 == 0;
    const BucketSort sort_bucket(layout, shift, records.data(), order, sorted_keys, sorted_rays, streaming);
    static thread_local BucketWords words;
    const auto bucket = [&](std::size_t d) {
        if (at[d + 1] > at[d]) sort_bucket(at[d], at[d + 1], words);
    };
    if (parts == 1)
        for (std::size_t d = 0; d < buckets; ++d) bucket(d);
    else
        tbb::parallel_for(std::size_t{0}, buckets, bucket);
    if (streaming) _mm_sfence();
}

}  // namespace

void sort_rays(std::span<const Ray> rays, std::span<const std::uint32_t> keys, std::span<const std::uint32_t> hashes,
               std::span<std::uint32_t> order, std::span<std::uint32_t> sorted_keys, std::span<Ray> sorted_rays,
               int parts, RaySortBuffers& buffers) {
    order_rays(rays, keys, hashes, order, sorted_keys, sorted_rays, parts, buffers, Ordering::sorted, "sort_rays");
}

void bucket_rays(std::span<const Ray> rays, std::span<const std::uint32_t> keys, std::span<std::uint32_t> order,
                 std::span<std::uint32_t> sorted_keys, std::span<Ray> sorted_rays, int parts, RaySortBuffers& buffers) {
    order_rays(rays, keys, {}, order, sorted_keys, sorted_rays, parts, buffers, Ordering::buckets, "bucket_rays");
}

std::span<const SortRecord> bucket_records(std::span<const Ray> rays, std::span<const std::uint32_t> keys, int parts,
                                           RaySortBuffers& buffers) {
    order_rays(rays, keys, {}, {}, {}, {}, parts, buffers, Ordering::bucket_records, "bucket_records");
    return std::span<const SortRecord>(buffers.records.data(), rays.size());
}

}  // namespace beamtrace::stream
