// sort_events (radix sort of long lists) gives std::sort's order, bit for bit: positions with many
// ties, signed zeros, negative values, every event type.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <random>

#include "kdtree/split_events.hpp"

using namespace beamtrace;
using kd::AxisEvents;
using kd::SplitEvent;

namespace {

AxisEvents random_events(std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> grid(-50, 50), kind(0, 9);
    std::uniform_real_distribution<float> any(-1e6f, 1e6f);
    AxisEvents events;
    for (std::uint32_t tri = 0; events.size() < n; ++tri) {
        float p;
        switch (kind(rng)) {
            case 0: p = 0.0f; break;
            case 1: p = -0.0f; break;
            case 2: p = any(rng); break;
            case 3: p = std::ldexp(float(grid(rng)), -140); break;  // denormals
            default: p = float(grid(rng)) * 0.25f; break;              // ties
        }
        if (kind(rng) == 0) {
            events.emplace_back(p, tri, kd::kPlanar);
        } else {
            events.emplace_back(p, tri, kd::kStart);
            events.emplace_back(p + float(grid(rng) + 50) * 0.25f, tri, kd::kEnd);
        }
    }
    std::shuffle(events.begin(), events.end(), rng);
    return events;
}

}  // namespace

TEST(SplitEvents, SortEqualsStdSort) {
    AxisEvents scratch;
    for (std::size_t n : {std::size_t(10), std::size_t(4095), std::size_t(4096), std::size_t(100000)}) {
        for (std::uint32_t seed = 1; seed <= 3; ++seed) {
            AxisEvents a = random_events(n, seed), b = a;
            kd::sort_events(a, scratch);
            std::sort(b.begin(), b.end());
            ASSERT_EQ(a.size(), b.size());
            for (std::size_t i = 0; i < a.size(); ++i) {
                ASSERT_EQ(std::bit_cast<std::uint32_t>(a[i].pos), std::bit_cast<std::uint32_t>(b[i].pos))
                    << "n " << n << " seed " << seed << " at " << i;
                ASSERT_EQ(a[i].key, b[i].key) << "n " << n << " seed " << seed << " at " << i;
            }
        }
    }
}
