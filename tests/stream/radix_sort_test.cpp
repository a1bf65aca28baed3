// The radix sort gives std::stable_sort's order, on one part and on several.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include <tbb/task_arena.h>

#include "stream/radix_sort.hpp"

using namespace beamtrace::stream;

namespace {

void check(const std::vector<std::uint32_t>& keys, int parts) {
    std::vector<std::uint32_t> expected(keys.size());
    std::iota(expected.begin(), expected.end(), 0u);
    std::stable_sort(expected.begin(), expected.end(), [&](auto a, auto b) { return keys[a] < keys[b]; });
    std::vector<std::uint32_t> order(keys.size()), sorted(keys.size());
    SortBuffers buffers;
    tbb::task_arena arena(parts);
    arena.execute([&] { sort_by_key(keys, order, sorted, parts, buffers); });
    EXPECT_EQ(order, expected);
    for (std::size_t k = 0; k < keys.size(); ++k) ASSERT_EQ(sorted[k], keys[order[k]]);
}

}  // namespace

TEST(StreamRadixSort, IsStableSortOnAnyKeys) {
    std::mt19937 random(11);
    for (std::size_t n : {0u, 1u, 2u, 17u, 1000u, 300000u}) {
        std::vector<std::uint32_t> keys(n);
        for (auto& k : keys) k = random();
        check(keys, 1);
        check(keys, 2);
        // Few distinct keys (stability matters), keys sharing digits (passes skipped), extremes.
        for (auto& k : keys) k = random() % 7 == 0 ? 0xFFFFFFFFu : (random() % 5) << 22;
        check(keys, 1);
        check(keys, 2);
    }
}
