// Groups cut from the sorted order: at most 16 rays, covering every ray once, runs of one origin
// together, for runs of any length (one light's millions of rays included).
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

#include <tbb/task_arena.h>

#include "stream/ray_groups.hpp"
#include "stream/ray_keys.hpp"

using namespace beamtrace;
using namespace beamtrace::stream;

namespace {

void expect_partition(const std::vector<RayGroup>& groups, std::uint32_t n) {
    std::uint32_t next = 0;
    for (const RayGroup& g : groups) {
        ASSERT_EQ(g.begin, next);
        if (g.kind == RayGroup::Kind::pencil || g.kind == RayGroup::Kind::origin) {
            ASSERT_GE(g.count, 1u);
            ASSERT_LE(g.count, 16u);
        }
        next += g.count;
    }
    EXPECT_EQ(next, n);
}

}  // namespace

TEST(StreamGroups, LongRunsOfOnePointMakeGroupsOfAtMost16) {
    const std::uint32_t n = 3'000'000;  // count * part overflows 32 bits here
    std::vector<Ray> rays(n, Ray{{0, 0, 0}, 0.0f, {1, 0, 0}, 1.0f});
    std::vector<std::uint32_t> keys(n, kPencilBit | (2u << kPointShift)), order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::vector<RayGroup> groups;
    cut_groups(rays, keys, order, 4, groups);
    expect_partition(groups, n);
    EXPECT_EQ(groups.size(), (n + 15) / 16);
    // On two threads: parts cut apart, still every ray once, groups of at most 16.
    tbb::task_arena arena(2);
    arena.execute([&] { cut_groups(rays, keys, order, 4, groups, 2); });
    expect_partition(groups, n);
}

TEST(StreamGroups, PartsNeverCutAnOriginCell) {
    // Many cells of 20 rays with one origin each: on two threads every group still has one origin.
    std::vector<Ray> rays;
    std::vector<std::uint32_t> keys;
    for (std::uint32_t c = 0; c < 20000; ++c)
        for (int i = 0; i < 20; ++i) {
            rays.push_back(Ray{{float(c), 0, 0}, 0.0f, {1, 0, float(i)}, 1.0f});
            keys.push_back(c);
        }
    std::vector<std::uint32_t> order(rays.size());
    std::iota(order.begin(), order.end(), 0u);
    std::vector<RayGroup> groups;
    tbb::task_arena arena(2);
    arena.execute([&] { cut_groups(rays, keys, order, 4, groups, 2); });
    expect_partition(groups, std::uint32_t(rays.size()));
    EXPECT_EQ(groups.size(), 40000u);  // 20 rays: 10 + 10
    for (const RayGroup& g : groups) {
        EXPECT_EQ(g.kind, RayGroup::Kind::origin);
        EXPECT_EQ(rays[g.begin].org.x, rays[g.begin + g.count - 1].org.x);
    }
}

TEST(StreamGroups, RaysOfOneOriginMeetInTheirCell) {
    // Two origins in one cell, their rays interleaved: two groups, each of one origin; a lone ray and
    // a ray that describes no segment go alone.
    std::vector<Ray> rays;
    std::vector<std::uint32_t> keys;
    for (int i = 0; i < 12; ++i) {
        rays.push_back(Ray{{i % 2 ? 0.5f : 0.25f, 0, 0}, 0.0f, {1, 0, float(i)}, 1.0f});
        keys.push_back(7u);
    }
    rays.push_back(Ray{{0.9f, 0, 0}, 0.0f, {1, 0, 0}, 1.0f});
    keys.push_back(9u);
    rays.push_back(Ray{{0, 0, 0}, 0.0f, {0, 0, 0}, 1.0f});
    keys.push_back(kNoSegmentKey);
    std::vector<std::uint32_t> order(rays.size());
    std::iota(order.begin(), order.end(), 0u);
    std::vector<RayGroup> groups;
    cut_groups(rays, keys, order, 4, groups);
    expect_partition(groups, std::uint32_t(rays.size()));
    ASSERT_EQ(groups.size(), 4u);
    EXPECT_EQ(groups[0].kind, RayGroup::Kind::origin);
    EXPECT_EQ(groups[1].kind, RayGroup::Kind::origin);
    EXPECT_EQ(groups[0].count, 6u);
    EXPECT_EQ(groups[2].kind, RayGroup::Kind::single);
    EXPECT_EQ(groups[3].kind, RayGroup::Kind::no_segment);
    for (std::uint32_t k = 0; k < 6; ++k) {
        EXPECT_EQ(rays[k].org.x, 0.25f);  // the rays moved with their input indices
        EXPECT_EQ(order[k] % 2, 0u);
    }
}

TEST(StreamGroups, EachOriginOfACellMakesItsOwnGroupsWhateverTheirNumber) {
    // Cells of 5 and of 40 origins (past the count compared one by one, sorted instead), 4 rays
    // each, interleaved: every group holds one origin's 4 rays in their input order.
    for (int origins : {5, 40}) {
        std::vector<Ray> rays;
        std::vector<std::uint32_t> keys;
        for (int i = 0; i < 4 * origins; ++i) {
            const int o = (i * 7) % origins;  // 7 is prime to 5 and 40: every origin 4 times
            rays.push_back(Ray{{0.5f + 1e-4f * float(o), 0.25f, float(o % 3)}, 0.0f, {1, 0, float(i)}, 1.0f});
            keys.push_back(3u);
        }
        std::vector<std::uint32_t> order(rays.size());
        std::iota(order.begin(), order.end(), 0u);
        const std::vector<Ray> input = rays;
        std::vector<RayGroup> groups;
        cut_groups(rays, keys, order, 4, groups);
        expect_partition(groups, std::uint32_t(rays.size()));
        ASSERT_EQ(groups.size(), std::size_t(origins)) << origins;
        std::vector<int> seen(std::size_t(origins), 0);
        for (const RayGroup& g : groups) {
            EXPECT_EQ(g.kind, RayGroup::Kind::origin);
            ASSERT_EQ(g.count, 4u);
            for (std::uint32_t k = g.begin; k < g.begin + g.count; ++k) {
                EXPECT_EQ(rays[k].org.x, rays[g.begin].org.x);
                EXPECT_EQ(rays[k].org.z, rays[g.begin].org.z);
                EXPECT_EQ(rays[k].dir.z, input[order[k]].dir.z);  // moved with its index
                if (k > g.begin) {
                    EXPECT_LT(order[k - 1], order[k]);  // stable
                }
            }
            ++seen[std::size_t(std::lround((rays[g.begin].org.x - 0.5f) / 1e-4f))];
        }
        for (int s : seen) EXPECT_EQ(s, 1);
    }
}
