// Double-precision segment distances and the clipping of rays to the scene.
#include "oracle/ray_geometry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "hand_scenes.hpp"

namespace beamtrace::oracle {
namespace {

double dist(Double3 a, Double3 b) {
    return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z));
}
Double3 lerp(Double3 a, Double3 b, double s) {
    return {a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z)};
}

TEST(RayGeometry, SegmentDistanceKnownCases) {
    // Skew perpendicular segments one unit apart, closest points inside both.
    EXPECT_DOUBLE_EQ(segment_distance({0, 0, 0}, {2, 0, 0}, {1, -1, 1}, {1, 1, 1}), 1.0);
    // Crossing segments.
    EXPECT_DOUBLE_EQ(segment_distance({0, 0, 0}, {2, 2, 0}, {0, 2, 0}, {2, 0, 0}), 0.0);
    // Parallel, overlapping in x.
    EXPECT_DOUBLE_EQ(segment_distance({0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {2, 1, 0}), 1.0);
    // Parallel, disjoint: endpoint (1,0,0) to (3,1,0).
    EXPECT_DOUBLE_EQ(segment_distance({0, 0, 0}, {1, 0, 0}, {3, 1, 0}, {4, 1, 0}), std::sqrt(5.0));
    // Collinear and disjoint.
    EXPECT_DOUBLE_EQ(segment_distance({0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {5, 0, 0}), 2.0);
    // Point against segment, and point against point.
    EXPECT_DOUBLE_EQ(segment_distance({1, 3, 0}, {1, 3, 0}, {0, 0, 0}, {2, 0, 0}), 3.0);
    EXPECT_DOUBLE_EQ(segment_distance({1, 1, 1}, {1, 1, 1}, {1, 1, 3}, {1, 1, 3}), 2.0);
    // Closest point of one line lies outside its segment: clamp to the endpoint.
    EXPECT_DOUBLE_EQ(segment_distance({0, 0, 0}, {1, 0, 0}, {3, -1, 2}, {3, 1, 2}), std::sqrt(4.0 + 4.0));
    // Very long ray segment against a tiny edge 1e-9 away.
    EXPECT_NEAR(segment_distance({-1e4, 0, 0}, {1e4, 0, 0}, {0.5, 1e-9, -1e-3}, {0.5, 1e-9, 1e-3}), 1e-9, 1e-12);
}

TEST(RayGeometry, SegmentDistanceAgreesWithSampling) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int trial = 0; trial < 200; ++trial) {
        const Double3 p0{u(rng), u(rng), u(rng)}, p1{u(rng), u(rng), u(rng)};
        Double3 q0{u(rng), u(rng), u(rng)}, q1{u(rng), u(rng), u(rng)};
        if (trial % 4 == 0) {  // nearly parallel pairs
            q0 = {p0.x + 0.3, p0.y + 0.1, p0.z};
            q1 = {p1.x + 0.3, p1.y + 0.1, p1.z + 1e-9};
        }
        const int n = 400;
        double sampled = 1e300;
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n; ++j)
                sampled = std::min(sampled, dist(lerp(p0, p1, double(i) / n), lerp(q0, q1, double(j) / n)));
        const double d = segment_distance(p0, p1, q0, q1);
        const double step = (dist(p0, p1) + dist(q0, q1)) / n;
        EXPECT_LE(d, sampled + 1e-12) << trial;
        EXPECT_GE(d, sampled - step) << trial;
    }
}

TEST(RayGeometry, ClipToScene) {
    const Scene s = test::cube();  // centre 0, diagonal sqrt(12)
    const RaySegment inf = clip_to_scene(s, Ray{{0, 0, -10}, 0.0f, {0, 0, 2}, kInfinity});
    ASSERT_FALSE(inf.empty);
    EXPECT_DOUBLE_EQ(inf.a.z, -10.0);
    EXPECT_GT(inf.b.z, 1.0);  // ends past the box
    EXPECT_NEAR(inf.b.z, -10.0 + (10.0 + std::sqrt(12.0)), 1e-5);
    const RaySegment bounded = clip_to_scene(s, Ray{{0, 0, -10}, 1.0f, {0, 0, 2}, 3.0f});
    EXPECT_DOUBLE_EQ(bounded.a.z, -8.0);
    EXPECT_DOUBLE_EQ(bounded.b.z, -4.0);
    EXPECT_TRUE(clip_to_scene(s, Ray{{0, 0, -10}, 3.0f, {0, 0, 1}, 1.0f}).empty);
    EXPECT_TRUE(clip_to_scene(s, Ray{{0, 0, -10}, 0.0f, {0, 0, 0}, 1.0f}).empty);
    EXPECT_TRUE(clip_to_scene(s, Ray{{0, 0, -10}, 100.0f, {0, 0, 1}, kInfinity}).empty);  // starts beyond the scene
    EXPECT_EQ(edge_distance(s.triangle(0), RaySegment{}), std::numeric_limits<double>::infinity());
}

TEST(RayGeometry, EdgeDistanceAndBruteForceSearch) {
    const Scene s = test::one_triangle();
    EXPECT_NEAR(grazing_distance(s), 1e-5 * std::sqrt(8.0), 1e-12);
    const RaySegment centre = clip_to_scene(s, Ray{{0.5f, 0.5f, -2}, 0.0f, {0, 0, 1}, kInfinity});
    EXPECT_NEAR(edge_distance(s.triangle(0), centre), 0.5, 1e-7);
    EXPECT_FALSE(near_edge_of_any(s, centre, 0.4));
    EXPECT_TRUE(near_edge_of_any(s, centre, 0.6));
    EXPECT_FALSE(near_edge_of_any(s, RaySegment{}, 1.0));
}

}  // namespace
}  // namespace beamtrace::oracle
