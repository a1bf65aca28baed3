// The Embree oracle against hand-computed hits, packets against single rays, edge cases of the ray
// semantics and concurrent use.
#include "oracle/embree_oracle.hpp"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "hand_scenes.hpp"

namespace beamtrace::oracle {
namespace {

using test::cube;
using test::one_triangle;
using test::two_triangles;
using test::with_degenerates;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

Ray make_ray(Float3 org, Float3 dir, float tnear = 0.0f, float tfar = kInfinity) { return Ray{org, tnear, dir, tfar}; }

TEST(EmbreeOracle, HitOnOneTriangleMatchesHandComputation) {
    const EmbreeOracle o(one_triangle());
    // Point (x, y, 1) of the triangle has u = x / 2, v = y / 2.
    Hit h = o.intersect1(make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 1}));
    ASSERT_TRUE(h.hit());
    EXPECT_EQ(h.triangle, 0u);
    EXPECT_NEAR(h.t, 3.0f, 1e-6f);
    EXPECT_NEAR(h.u, 0.25f, 1e-6f);
    EXPECT_NEAR(h.v, 0.125f, 1e-6f);

    // Oblique ray: (1, 1, -1) + 2 * (-0.25, 0, 1) = (0.5, 1, 1).
    h = o.intersect1(make_ray({1.0f, 1.0f, -1.0f}, {-0.25f, 0.0f, 1.0f}));
    ASSERT_TRUE(h.hit());
    EXPECT_NEAR(h.t, 2.0f, 1e-6f);
    EXPECT_NEAR(h.u, 0.25f, 1e-6f);
    EXPECT_NEAR(h.v, 0.5f, 1e-6f);

    // t is measured in units of |dir|.
    h = o.intersect1(make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 4}));
    ASSERT_TRUE(h.hit());
    EXPECT_NEAR(h.t, 0.75f, 1e-6f);

    // From the other side.
    h = o.intersect1(make_ray({0.2f, 1.0f, 3.0f}, {0, 0, -1}));
    ASSERT_TRUE(h.hit());
    EXPECT_NEAR(h.t, 2.0f, 1e-6f);
    EXPECT_NEAR(h.u, 0.1f, 1e-6f);
    EXPECT_NEAR(h.v, 0.5f, 1e-6f);
}

TEST(EmbreeOracle, MissesAndSegmentLimits) {
    const EmbreeOracle o(one_triangle());
    EXPECT_FALSE(o.intersect1(make_ray({1.5f, 1.5f, -2.0f}, {0, 0, 1})).hit());               // beside the hypotenuse
    EXPECT_FALSE(o.intersect1(make_ray({0.5f, 0.25f, 2.0f}, {0, 0, 1})).hit());               // triangle behind
    EXPECT_FALSE(o.intersect1(make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 1}, 0.0f, 2.5f)).hit());  // too short
    EXPECT_FALSE(o.intersect1(make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 1}, 3.5f)).hit());        // starts past it
    EXPECT_TRUE(o.intersect1(make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 1}, 2.5f, 3.5f)).hit());
    EXPECT_FALSE(o.occluded1(make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 1}, 0.0f, 2.5f)));
    EXPECT_TRUE(o.occluded1(make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 1}, 0.0f, 3.5f)));
}

TEST(EmbreeOracle, ReversedNaNAndZeroDirectionRaysReportNothing) {
    const EmbreeOracle o(one_triangle());
    const std::vector<Ray> rays = {
        make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 1}, 4.0f, 2.0f),  // tfar < tnear around the hit
        make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 0}),              // zero direction
        make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 1}, kNaN),        // NaN tnear
        make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 1}, 0.0f, kNaN),  // NaN tfar
        make_ray({kNaN, 0.25f, -2.0f}, {0, 0, 1}),              // NaN origin
        make_ray({0.5f, 0.25f, -2.0f}, {0, kNaN, 1}),           // NaN direction
        make_ray({0.5f, 0.25f, -kInfinity}, {0, 0, 1}),         // infinite origin
        make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 1}, kInfinity),   // infinite tnear
        make_ray({0.5f, 0.25f, -2.0f}, {0, 0, 1}, -kInfinity),  // infinite negative tnear
    };
    Packet16 p{};
    for (std::size_t i = 0; i < rays.size(); ++i) {
        SCOPED_TRACE(i);
        EXPECT_FALSE(o.intersect1(rays[i]).hit());
        EXPECT_FALSE(o.occluded1(rays[i]));
        p.set_ray(int(i), rays[i]);
        p.active |= 1u << i;
    }
    PacketHits16 hits;
    o.intersect16(p, hits);
    for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_FALSE(hits.hit(int(i)).hit()) << i;
    EXPECT_EQ(o.occluded16(p), 0u);
}

TEST(EmbreeOracle, NegativeTnearReachesBehindTheOrigin) {
    const EmbreeOracle o(one_triangle());
    const Ray r = make_ray({0.5f, 0.25f, 5.0f}, {0, 0, 1}, -10.0f);
    const Hit h = o.intersect1(r);
    ASSERT_TRUE(h.hit());
    EXPECT_NEAR(h.t, -4.0f, 1e-5f);
    EXPECT_NEAR(h.u, 0.25f, 1e-6f);
    EXPECT_NEAR(h.v, 0.125f, 1e-6f);
    EXPECT_TRUE(o.occluded1(r));
    EXPECT_FALSE(o.occluded1(make_ray({0.5f, 0.25f, 5.0f}, {0, 0, 1}, -3.0f)));
    Packet16 p{};
    p.set_ray(5, r);
    p.active = 1u << 5;
    PacketHits16 hits;
    o.intersect16(p, hits);
    EXPECT_EQ(hits.triangle[5], 0u);
    EXPECT_NEAR(hits.t[5], -4.0f, 1e-5f);
    EXPECT_EQ(o.occluded16(p), 1u << 5);
}

TEST(EmbreeOracle, DirectionsBeyondEmbreesRangeAreScaledOriginsBeyondItReportNothing) {
    // Embree aborts on components above 1.844e18 (ray.valid()); the oracle must never pass one on.
    const EmbreeOracle o(one_triangle());
    for (float scale : {1e18f, 2e18f, 1e30f, 3e38f}) {
        SCOPED_TRACE(scale);
        const Ray r = make_ray({0.5f, 0.25f, -2.0f}, {0, 0, scale});
        const Hit h = o.intersect1(r);
        ASSERT_TRUE(h.hit());
        EXPECT_FLOAT_EQ(h.t, 3.0f / scale);
        EXPECT_NEAR(h.u, 0.25f, 1e-6f);
        EXPECT_TRUE(o.occluded1(r));
        EXPECT_FALSE(o.occluded1(make_ray({0.5f, 0.25f, -2.0f}, {0, 0, scale}, 0.0f, 2.0f / scale)));
        Packet16 p{};
        p.set_ray(3, r);
        p.active = 1u << 3;
        PacketHits16 hits;
        o.intersect16(p, hits);
        EXPECT_EQ(hits.triangle[3], 0u);
        EXPECT_FLOAT_EQ(hits.t[3], 3.0f / scale);
        EXPECT_EQ(o.occluded16(p), 1u << 3);
    }
    for (const Ray& r : {make_ray({0.5f, 0.25f, -2e18f}, {0, 0, 1}), make_ray({0.5f, 3e38f, -2.0f}, {0, 0, 1}),
                         make_ray({0.5f, 0.25f, 1.0f}, {0, 0, 1e30f}, -1e10f)}) {
        EXPECT_FALSE(o.intersect1(r).hit());
        EXPECT_FALSE(o.occluded1(r));
        Packet16 p{};
        p.set_ray(0, r);
        p.active = 1u;
        PacketHits16 hits;
        o.intersect16(p, hits);
        EXPECT_FALSE(hits.hit(0).hit());
        EXPECT_EQ(o.occluded16(p), 0u);
    }
}

TEST(EmbreeOracle, AxisParallelRaysInsideACube) {
    const EmbreeOracle o(cube());
    // From the centre along each axis: face order -x, +x, -y, +y, -z, +z.
    const Float3 dirs[6] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    for (int f = 0; f < 6; ++f) {
        SCOPED_TRACE(f);
        const Hit h = o.intersect1(make_ray({0.1f, 0.2f, 0.3f}, dirs[f]));
        ASSERT_TRUE(h.hit());
        EXPECT_TRUE(h.triangle == std::uint32_t(2 * f) || h.triangle == std::uint32_t(2 * f + 1)) << h.triangle;
        const float coord = f < 2 ? 0.1f : (f < 4 ? 0.2f : 0.3f);
        EXPECT_NEAR(h.t, (f % 2 == 0) ? 1.0f + coord : 1.0f - coord, 1e-6f);
    }
    // From outside, with two zero direction components.
    const Hit h = o.intersect1(make_ray({5.0f, 0.5f, -0.25f}, {-2, 0, 0}));
    ASSERT_TRUE(h.hit());
    EXPECT_TRUE(h.triangle == 2u || h.triangle == 3u);
    EXPECT_NEAR(h.t, 2.0f, 1e-6f);
}

TEST(EmbreeOracle, DegenerateTrianglesAreNeverHitAndIdsStayTheScenes) {
    const Scene s = with_degenerates();
    ASSERT_EQ(s.degenerate_count(), 4u);
    const EmbreeOracle o(s);
    EXPECT_EQ(o.embree_triangle_count(), 1u);
    const std::vector<Ray> at_degenerates = {
        make_ray({0.5f, 0.0f, 5.0f}, {0, 0, -1}, 0.0f, 4.5f),    // through the collinear one at z = 1
        make_ray({-1.0f, 0.0f, 1.0f}, {1, 0, 0}),                // along it
        make_ray({0.5f, -1.0f, 1.0f}, {0, 1, 0}),                // across it
        make_ray({0.5f, 0.5f, 5.0f}, {0, 0, -1}, 0.0f, 4.5f),    // through the repeated-corner one and the diagonal one
        make_ray({-1.0f, -1.0f, 2.0f}, {1, 1, 0}),               // along the repeated-corner one
        make_ray({0.25f, 0.25f, 5.0f}, {0, 0, -1}, 0.0f, 4.5f),  // through the point triangle
        make_ray({-1.0f, -1.0f, 4.0f}, {1, 1, 0}),               // along the diagonal one
    };
    for (std::size_t i = 0; i < at_degenerates.size(); ++i) {
        EXPECT_FALSE(o.intersect1(at_degenerates[i]).hit()) << i;
        EXPECT_FALSE(o.occluded1(at_degenerates[i])) << i;
    }
    // The good triangle keeps its id 2.
    const Hit h = o.intersect1(make_ray({0.25f, 0.5f, 10.0f}, {0, 0, -1}));
    ASSERT_TRUE(h.hit());
    EXPECT_EQ(h.triangle, 2u);
    EXPECT_NEAR(h.t, 10.0f, 1e-6f);
    EXPECT_NEAR(h.u, 0.25f, 1e-6f);
    EXPECT_NEAR(h.v, 0.5f, 1e-6f);
}

TEST(EmbreeOracle, OnlyDegenerateTrianglesGiveAnEmptyOracle) {
    const std::vector<Float3> v = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    const std::vector<std::uint32_t> i = {0, 1, 2};
    const EmbreeOracle o(Scene(v, i));
    EXPECT_EQ(o.embree_triangle_count(), 0u);
    EXPECT_FALSE(o.intersect1(make_ray({1, 0, 1}, {0, 0, -1})).hit());
    EXPECT_FALSE(o.occluded1(make_ray({-1, 0, 0}, {1, 0, 0})));
}

// Random rays from a shell around the cube towards random points inside it (some miss).
std::vector<Ray> random_rays(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < n; ++i) {
        const Float3 org{4 * u(rng), 4 * u(rng), 4 * u(rng)};
        const Float3 target{1.3f * u(rng), 1.3f * u(rng), 1.3f * u(rng)};
        const float tfar = (i % 5 == 0) ? 0.5f + 2.0f * (u(rng) + 1.0f) : kInfinity;
        rays.push_back(make_ray(org, target - org, 0.0f, tfar));
    }
    return rays;
}

TEST(EmbreeOracle, PacketsEqualSingleRays) {
    const EmbreeOracle o(cube());
    const auto rays = random_rays(16 * 64, 7);
    std::mt19937 rng(11);
    int hits_seen = 0;
    for (std::size_t base = 0; base < rays.size(); base += 16) {
        Packet16 p{};
        for (int i = 0; i < 16; ++i) p.set_ray(i, rays[base + i]);
        p.active = (base == 0) ? 0xFFFFu : (rng() & 0xFFFFu);
        PacketHits16 hits;
        o.intersect16(p, hits);
        const std::uint32_t occluded = o.occluded16(p);
        for (int i = 0; i < 16; ++i) {
            SCOPED_TRACE(base + i);
            const bool active = (p.active >> i) & 1u;
            const Hit single = o.intersect1(rays[base + i]);
            const Hit packet = hits.hit(i);
            if (!active) {
                EXPECT_FALSE(packet.hit());
                EXPECT_FALSE((occluded >> i) & 1u);
                continue;
            }
            EXPECT_EQ(packet.triangle, single.triangle);
            EXPECT_EQ(bool((occluded >> i) & 1u), o.occluded1(rays[base + i]));
            EXPECT_EQ(bool((occluded >> i) & 1u), single.hit());
            if (single.hit()) {
                ++hits_seen;
                EXPECT_NEAR(packet.t, single.t, 1e-6f * std::max(1.0f, single.t));
                EXPECT_NEAR(packet.u, single.u, 1e-6f);
                EXPECT_NEAR(packet.v, single.v, 1e-6f);
            }
        }
    }
    EXPECT_GT(hits_seen, 100);
}

TEST(EmbreeOracle, InactiveLanesReportNoHitEvenWhenTheirRaysWouldHit) {
    const EmbreeOracle o(one_triangle());
    Packet16 p{};
    for (int i = 0; i < 16; ++i) p.set_ray(i, make_ray({0.1f + 0.05f * i, 0.2f, -1.0f}, {0, 0, 1}));
    p.active = 0x5A5Au;
    PacketHits16 hits;
    for (int i = 0; i < 16; ++i) hits.set_hit(i, Hit{1.0f, 0u, 0.5f, 0.5f});  // stale values to overwrite
    o.intersect16(p, hits);
    for (int i = 0; i < 16; ++i) {
        const bool active = (p.active >> i) & 1u;
        EXPECT_EQ(hits.triangle[i], active ? 0u : kNoHit) << i;
        if (active)
            EXPECT_NEAR(hits.t[i], 2.0f, 1e-6f) << i;
        else
            EXPECT_EQ(hits.t[i], kInfinity) << i;
    }
    EXPECT_EQ(o.occluded16(p), 0x5A5Au);
    p.active = 0;
    o.intersect16(p, hits);
    for (int i = 0; i < 16; ++i) EXPECT_FALSE(hits.hit(i).hit());
    EXPECT_EQ(o.occluded16(p), 0u);
}

TEST(EmbreeOracle, ConcurrentQueriesMatchSequentialOnes) {
    const EmbreeOracle o(cube());
    const auto rays = random_rays(20000, 3);
    std::vector<Hit> sequential(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) sequential[i] = o.intersect1(rays[i]);
    std::vector<Hit> parallel(rays.size());
    std::vector<char> occluded(rays.size());
    tbb::parallel_for(std::size_t{0}, rays.size(), [&](std::size_t i) {
        parallel[i] = o.intersect1(rays[i]);
        occluded[i] = o.occluded1(rays[i]);
    });
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(parallel[i].triangle, sequential[i].triangle) << i;
        ASSERT_EQ(parallel[i].t, sequential[i].t) << i;
        ASSERT_EQ(bool(occluded[i]), sequential[i].hit()) << i;
    }
}

TEST(EmbreeOracle, BuildTimeAndMeasuredMemory) {
    const EmbreeOracle small(one_triangle());
    EXPECT_GT(small.build_seconds(), 0.0);
    EXPECT_GT(small.memory_bytes(), 0u);

    // A grid of 2 * 64 * 64 triangles needs at least its vertex and index buffers.
    std::vector<Float3> v;
    std::vector<std::uint32_t> idx;
    const int n = 64;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) v.push_back({float(x), float(y), 0.1f * float((x * 7 + y * 3) % 5)});
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const std::uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
            idx.insert(idx.end(), {a, b, d, a, d, c});
        }
    const EmbreeOracle big(Scene(v, idx));
    EXPECT_GE(big.memory_bytes(), v.size() * sizeof(Float3) + idx.size() * sizeof(std::uint32_t));
    EXPECT_GT(big.memory_bytes(), small.memory_bytes());
    const Hit h = big.intersect1(make_ray({10.25f, 20.5f, 5.0f}, {0, 0, -1}));
    ASSERT_TRUE(h.hit());
    EXPECT_GT(h.t, 4.0f);
    EXPECT_LT(h.t, 5.0f);
}

TEST(EmbreeOracle, MovedOracleKeepsWorking) {
    EmbreeOracle a(two_triangles());
    EmbreeOracle b(std::move(a));
    Hit h = b.intersect1(make_ray({0.75f, 0.25f, 1.0f}, {0, 0, -1}));
    EXPECT_EQ(h.triangle, 0u);
    EmbreeOracle c(one_triangle());
    c = std::move(b);
    h = c.intersect1(make_ray({0.25f, 0.75f, 1.0f}, {0, 0, -1}));
    EXPECT_EQ(h.triangle, 1u);
    EXPECT_NEAR(h.t, 1.0f, 1e-6f);
}

}  // namespace
}  // namespace beamtrace::oracle
