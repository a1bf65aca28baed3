// The stream sort gives std::stable_sort's order by key (and, for rays keyed by their origin's cell,
// by the top bits of their origin's hash), on one part and on several; the rays of one origin come
// out next to each other.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include <tbb/task_arena.h>

#include "stream/radix_sort.hpp"
#include "stream/ray_keys.hpp"

using namespace beamtrace;
using namespace beamtrace::stream;

namespace {

// What the sort orders by: the key, then (origin-cell keys, when rays are given) the hash's top bits.
std::vector<std::uint32_t> hashes_of(const std::vector<Ray>& rays) {
    std::vector<std::uint32_t> h(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) h[i] = origin_hash(rays[i]);
    return h;
}

std::uint64_t sort_key(const std::vector<std::uint32_t>& keys, const std::vector<Ray>& rays, std::uint32_t i) {
    const int h = rays.empty() ? 0 : hash_bits(keys.size());
    const bool hashed = h > 0 && (keys[i] & kPencilBit) == 0;
    return (std::uint64_t(keys[i]) << 32) | (hashed ? std::uint64_t(origin_hash(rays[i]) >> (32 - h)) << 16 : 0);
}

void check(const std::vector<std::uint32_t>& keys, const std::vector<Ray>& rays, int parts) {
    std::vector<std::uint32_t> expected(keys.size());
    std::iota(expected.begin(), expected.end(), 0u);
    std::stable_sort(expected.begin(), expected.end(),
                     [&](auto a, auto b) { return sort_key(keys, rays, a) < sort_key(keys, rays, b); });
    std::vector<std::uint32_t> order(keys.size()), sorted(keys.size());
    SortBuffers buffers;
    tbb::task_arena arena(parts);
    const std::vector<std::uint32_t> hashes = hashes_of(rays);
    arena.execute([&] { sort_by_key(keys, hashes, order, sorted, parts, buffers); });
    EXPECT_EQ(order, expected);
    for (std::size_t k = 0; k < keys.size(); ++k) ASSERT_EQ(sorted[k], keys[order[k]]);
}

}  // namespace

TEST(StreamRadixSort, IsStableSortOnAnyKeys) {
    std::mt19937 random(11);
    for (std::size_t n : {0u, 1u, 2u, 17u, 1000u, 300000u}) {
        std::vector<std::uint32_t> keys(n);
        for (auto& k : keys) k = random();
        std::vector<Ray> rays(n);
        for (auto& r : rays) r = Ray{{float(random() % 50), float(random() % 3), 0.5f}, 0.0f, {1, 0, 0}, 1.0f};
        for (const std::vector<Ray>& with : {std::vector<Ray>{}, rays}) {
            check(keys, with, 1);
            check(keys, with, 2);
            // Few distinct keys (stability matters), keys sharing digits (passes skipped), extremes.
            std::vector<std::uint32_t> few(n);
            for (auto& k : few) k = random() % 7 == 0 ? 0xFFFFFFFFu : (random() % 5) << 22;
            check(few, with, 1);
            check(few, with, 2);
        }
    }
}

TEST(StreamRadixSort, RaysOfOneOriginComeOutTogetherUnlessTheirHashesMeet) {
    // Cells of 40 origins, 4 rays each, interleaved: every origin whose hash bits no other origin of
    // its cell shares has its 4 rays next to each other, in their input order.
    std::vector<std::uint32_t> keys;
    std::vector<Ray> rays;
    const int origins = 40;
    for (std::uint32_t cell = 0; cell < 50; ++cell)
        for (int i = 0; i < 4 * origins; ++i) {
            const int o = (i * 7) % origins;  // 7 is prime to 40: every origin 4 times
            rays.push_back(Ray{{float(cell) + 1e-4f * float(o), 0.25f, float(o % 3)}, 0.0f, {1, 0, float(i)}, 1.0f});
            keys.push_back(cell);
        }
    std::vector<std::uint32_t> order(keys.size()), sorted(keys.size());
    SortBuffers buffers;
    sort_by_key(keys, hashes_of(rays), order, sorted, 1, buffers);
    const int h = hash_bits(keys.size());
    ASSERT_GT(h, 0);
    int together = 0;
    for (std::uint32_t cell = 0; cell < 50; ++cell) {
        std::map<std::uint32_t, int> hashes;  // hash bits -> origins of the cell with them
        for (int o = 0; o < origins; ++o)
            ++hashes[origin_hash(Ray{{float(cell) + 1e-4f * float(o), 0.25f, float(o % 3)}, 0, {1, 0, 0}, 1}) >> (32 - h)];
        for (std::uint32_t k = cell * 4 * origins; k < (cell + 1) * 4 * origins; k += 4) {
            const Ray& first = rays[order[k]];
            if (hashes[origin_hash(first) >> (32 - h)] > 1) continue;
            for (std::uint32_t j = 1; j < 4; ++j) {
                ASSERT_EQ(rays[order[k + j]].org.x, first.org.x);
                ASSERT_EQ(rays[order[k + j]].org.z, first.org.z);
                ASSERT_LT(order[k + j - 1], order[k + j]);
            }
            ++together;
        }
    }
    EXPECT_GT(together, 50 * origins * 9 / 10);
}

TEST(StreamGather, CopiesEveryRayIntoTheOrderAboveAndBelowTheStreamingSize) {
    // Streams of a million rays and more take streaming stores; smaller ones plain copies.
    std::mt19937 random(12);
    for (std::size_t n : {std::size_t{1000}, (std::size_t{1} << 20) + 37}) {
        std::vector<Ray> rays(n);
        for (std::size_t i = 0; i < n; ++i)
            rays[i] = Ray{{float(i), float(i % 7), -float(i)}, float(i % 3), {1, float(i % 5), 2}, float(i) + 0.5f};
        std::vector<std::uint32_t> order(n);
        std::iota(order.begin(), order.end(), 0u);
        std::shuffle(order.begin(), order.end(), random);
        std::vector<Ray> out(n);
        gather_in_order(rays, order, 0, n / 3, out);
        gather_in_order(rays, order, n / 3, n, out);
        for (std::size_t k = 0; k < n; ++k) {
            const Ray& want = rays[order[k]];
            ASSERT_EQ(std::memcmp(&out[k], &want, sizeof(Ray)), 0) << n << " ray " << k;
        }
    }
}
