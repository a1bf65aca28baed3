// Groups cut from the sorted keys: every ray once, pencils of at most 16, a cell's rays in groups of
// at most kMaxCellGroup that never straddle a change of key, short runs one by one, for runs of any
// length (one light's millions of rays included).
#include <gtest/gtest.h>

#include <vector>

#include <tbb/task_arena.h>

#include "stream/ray_groups.hpp"
#include "stream/ray_keys.hpp"

using namespace beamtrace;
using namespace beamtrace::stream;

namespace {

void expect_partition(const std::vector<RayGroup>& groups, const std::vector<std::uint32_t>& keys) {
    std::uint32_t next = 0;
    for (const RayGroup& g : groups) {
        ASSERT_EQ(g.begin, next);
        ASSERT_GE(g.count, 1u);
        if (g.kind == RayGroup::Kind::pencil) {
            ASSERT_LE(g.count, 16u);
        }
        if (g.kind == RayGroup::Kind::cell) {
            ASSERT_LE(g.count, kMaxCellGroup);
            for (std::uint32_t k = g.begin; k < g.begin + g.count; ++k) ASSERT_EQ(keys[k], keys[g.begin]);
        }
        next += g.count;
    }
    EXPECT_EQ(next, keys.size());
}

}  // namespace

TEST(StreamGroups, LongRunsOfOnePointMakeGroupsOfAtMost16) {
    const std::uint32_t n = 3'000'000;  // count * part overflows 32 bits here
    const std::vector<std::uint32_t> keys(n, kPencilBit | (2u << kPointShift));
    std::vector<RayGroup> groups;
    cut_groups(keys, 4, groups);
    expect_partition(groups, keys);
    EXPECT_EQ(groups.size(), (n + 15) / 16);
    // On two threads: parts cut apart, still every ray once, groups of at most 16.
    tbb::task_arena arena(2);
    arena.execute([&] { cut_groups(keys, 4, groups, 2); });
    expect_partition(groups, keys);
}

TEST(StreamGroups, PartsNeverCutAnOriginCell) {
    // Many cells of 20 rays: on two threads every cell is still one group.
    std::vector<std::uint32_t> keys;
    for (std::uint32_t c = 0; c < 20000; ++c) keys.insert(keys.end(), 20, c);
    std::vector<RayGroup> groups;
    tbb::task_arena arena(2);
    arena.execute([&] { cut_groups(keys, 4, groups, 2); });
    expect_partition(groups, keys);
    ASSERT_EQ(groups.size(), 20000u);
    for (const RayGroup& g : groups) {
        EXPECT_EQ(g.kind, RayGroup::Kind::cell);
        EXPECT_EQ(g.count, 20u);
    }
}

TEST(StreamGroups, ShortRunsGoOneByOneAndLongCellsInParts) {
    // A cell of 3 rays (below min_group_rays 4), a lone ray, a cell of 2,500 rays, a pencil run of
    // 3, rays without a segment.
    std::vector<std::uint32_t> keys(3, 5u);
    keys.push_back(6u);
    keys.insert(keys.end(), 2500, 7u);
    keys.insert(keys.end(), 3, kPencilBit | (1u << kPointShift) | 9u);
    keys.insert(keys.end(), 2, kNoSegmentKey);
    std::vector<RayGroup> groups;
    cut_groups(keys, 4, groups);
    expect_partition(groups, keys);
    ASSERT_EQ(groups.size(), 6u);
    EXPECT_EQ(groups[0].kind, RayGroup::Kind::single);  // the 3 and the lone ray, merged
    EXPECT_EQ(groups[0].count, 4u);
    for (int i = 1; i <= 3; ++i) {
        EXPECT_EQ(groups[std::size_t(i)].kind, RayGroup::Kind::cell);  // 2,500 = 833 + 833 + 834
        EXPECT_GE(groups[std::size_t(i)].count, 833u);
    }
    EXPECT_EQ(groups[4].kind, RayGroup::Kind::single);
    EXPECT_EQ(groups[4].count, 3u);
    EXPECT_EQ(groups[5].kind, RayGroup::Kind::no_segment);
}
