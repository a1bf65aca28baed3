// The sort and gather in one (stream/ray_sort.hpp) gives what the sort by key and the gather give
// apart, bit for bit: the same order, keys and rays, on one part and on several, for keys spread
// over every bit, keys sharing their top bits, few distinct keys, and streams with and without
// origin hashes.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <random>
#include <vector>

#include <tbb/task_arena.h>

#include "beamtrace/error.hpp"
#include "stream/radix_sort.hpp"
#include "stream/ray_keys.hpp"
#include "stream/ray_sort.hpp"

using namespace beamtrace;
using namespace beamtrace::stream;

namespace {

void expect_as_sort_then_gather(const std::vector<std::uint32_t>& keys, const std::vector<Ray>& rays, bool hashed,
                                int parts) {
    const std::size_t n = keys.size();
    std::vector<std::uint32_t> hashes;
    if (hashed)
        for (const Ray& r : rays) hashes.push_back(origin_hash(r));
    std::vector<std::uint32_t> order(n), sorted(n), want_order(n), want_sorted(n);
    std::vector<Ray> out(n), want_out(n);
    SortBuffers sort_buffers;
    sort_by_key(keys, hashes, want_order, want_sorted, 1, sort_buffers);
    gather_in_order(rays, want_order, 0, n, want_out);
    RaySortBuffers buffers;
    tbb::task_arena arena(parts);
    arena.execute([&] { sort_rays(rays, keys, hashes, order, sorted, out, parts, buffers); });
    ASSERT_EQ(order, want_order) << n << " rays, " << parts << " parts";
    ASSERT_EQ(sorted, want_sorted);
    ASSERT_EQ(n == 0 ? 0 : std::memcmp(out.data(), want_out.data(), n * sizeof(Ray)), 0);
}

std::vector<Ray> some_rays(std::size_t n, std::mt19937& random, int origins) {
    std::vector<Ray> rays(n);
    for (std::size_t i = 0; i < n; ++i) {
        const int o = int(random() % std::uint32_t(origins));
        rays[i] = Ray{{float(o % 97), float(o / 97) * 0.5f, -0.25f * float(o % 5)},
                      float(i % 3),
                      {1.0f, float(i % 11) - 5.0f, float(random() % 1000) * 1e-3f},
                      float(i) + 0.5f};
    }
    return rays;
}

}  // namespace

TEST(StreamRaySort, GivesTheSortByKeyAndTheGatherBitForBit) {
    std::mt19937 random(21);
    for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{47}, std::size_t{1000},
                          std::size_t{300000}, (std::size_t{1} << 20) + 5}) {
        const std::vector<Ray> rays = some_rays(n, random, 5000);
        std::vector<std::uint32_t> spread(n), top_shared(n), few(n), cells(n), narrow(n);
        for (std::size_t i = 0; i < n; ++i) {
            spread[i] = random();
            // Nine in ten share their top bits (one large bucket), their low bits spread.
            top_shared[i] = random() % 10 ? 0x12300000u | ((random() & 0xFFFFFu) >> (random() % 12)) : random() >> 1;
            few[i] = random() % 7 == 0 ? kNoSegmentKey : (random() % 5) << 22;
            // Origin-cell keys with a few pencils among them (as a mixed stream's).
            cells[i] =
                random() % 9 == 0 ? kPencilBit | (random() & 0xFFFFFu) : std::uint32_t(i % 4096) * 2654435761u >> 3;
            // Pencils of four points: few bits below the top digit (one radix pass in the buckets).
            narrow[i] = kPencilBit | (random() & 0x3FFFFFu);
        }
        for (const auto* keys : {&spread, &top_shared, &few, &cells, &narrow})
            for (bool hashed : {false, true})
                for (int parts : {1, 2}) expect_as_sort_then_gather(*keys, rays, hashed, parts);
    }
}

TEST(StreamRaySort, EveryRayOfOneKeyAndTheOnlyKey) {
    // One key and one origin for every ray: nothing varies, the input order is the sorted one.
    std::mt19937 random(22);
    const std::vector<Ray> rays = some_rays(200000, random, 1);
    expect_as_sort_then_gather(std::vector<std::uint32_t>(rays.size(), 77u), rays, true, 1);
    expect_as_sort_then_gather(std::vector<std::uint32_t>(rays.size(), 77u), rays, true, 2);
}

TEST(StreamRaySort, TheBucketPassOrdersByTheKeysTopDigitAndKeepsTheInputOrderWithinIt) {
    // Above and below the size of the staging lines and streaming stores, on one part and two.
    std::mt19937 random(23);
    for (std::size_t n : {std::size_t{1}, std::size_t{1000}, std::size_t{300000}, (std::size_t{1} << 20) + 3}) {
        const std::vector<Ray> rays = some_rays(n, random, 5000);
        std::vector<std::uint32_t> keys(n);
        for (auto& k : keys) k = random() >> 2;
        std::uint32_t any = 0, all = ~0u;
        for (const std::uint32_t k : keys) any |= k, all &= k;
        const int top = std::bit_width(any ^ all);
        const int digit = std::clamp(int(std::bit_width(n)) - 8, 1, kMaxBucketOrderBits);
        const int shift = std::max(0, top - digit);
        for (int parts : {1, 2}) {
            std::vector<std::uint32_t> order(n), sorted(n);
            std::vector<Ray, HugePageAllocator<Ray>> out(n);  // 16-byte aligned: large streams' streaming stores
            RaySortBuffers buffers;
            tbb::task_arena arena(parts);
            arena.execute([&] { bucket_rays(rays, keys, order, sorted, out, parts, buffers); });
            // The same order left in the records (each ray with its key and index), and each input
            // ray's position.
            RaySortBuffers record_buffers;
            std::span<const SortRecord> records;
            arena.execute([&] { records = bucket_records(rays, keys, parts, record_buffers); });
            ASSERT_EQ(records.size(), n);
            ASSERT_EQ(record_buffers.positions.size(), n);
            for (std::size_t k = 0; k < n; ++k) {
                ASSERT_EQ(std::uint32_t(records[k].word), order[k]) << "position " << k << " of " << n;
                ASSERT_EQ(record_buffers.positions[order[k]], k);
                ASSERT_EQ(std::uint32_t(records[k].word >> 32), sorted[k]);
                ASSERT_EQ(std::memcmp(&records[k].ray, &out[k], sizeof(Ray)), 0);
            }
            std::vector<bool> seen(n, false);
            for (std::size_t k = 0; k < n; ++k) {
                ASSERT_LT(order[k], n);
                ASSERT_FALSE(seen[order[k]]) << "ray " << order[k] << " twice";
                seen[order[k]] = true;
                ASSERT_EQ(sorted[k], keys[order[k]]);
                ASSERT_EQ(std::memcmp(&out[k], &rays[order[k]], sizeof(Ray)), 0);
                if (k == 0) continue;
                const std::uint32_t d0 = sorted[k - 1] >> shift, d1 = sorted[k] >> shift;
                ASSERT_LE(d0, d1) << "position " << k << " of " << n;
                if (d0 == d1) {
                    ASSERT_LT(order[k - 1], order[k]) << "position " << k << " of " << n;
                }
            }
        }
    }
}

TEST(StreamRaySort, RefusesSpansOfOtherSizes) {
    std::vector<Ray> rays(10);
    std::vector<std::uint32_t> keys(10), order(10), sorted(9);
    std::vector<Ray> out(10);
    RaySortBuffers buffers;
    EXPECT_THROW(sort_rays(rays, keys, {}, order, sorted, out, 1, buffers), Error);
    EXPECT_THROW(bucket_rays(rays, keys, order, sorted, out, 1, buffers), Error);
    const std::vector<std::uint32_t> short_keys(9);
    EXPECT_THROW(bucket_records(rays, short_keys, 1, buffers), Error);
}
