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

TEST(RayGeometry, EndDistanceAndBruteForceSearch) {
    // one_triangle(): corners (0,0,1), (2,0,1), (0,2,1). Rays up the z axis cross it at z = 1.
    const Scene s = test::one_triangle();
    const Triangle& tri = s.triangle(0);
    auto ray = [](Float3 org, Float3 dir, float tnear, float tfar) { return Ray{org, tnear, dir, tfar}; };
    const Float3 up{0, 0, 1};
    EXPECT_DOUBLE_EQ(end_distance(tri, ray({0.5f, 0.5f, -2}, up, 0.0f, 3.0f)), 0.0);
    EXPECT_NEAR(end_distance(tri, ray({0.5f, 0.5f, -2}, up, 0.0f, 2.5f)), 0.5, 1e-12);           // ends before it
    EXPECT_NEAR(end_distance(tri, ray({0.5f, 0.5f, -2}, up, 0.0f, 3.25f)), 0.25, 1e-12);         // ends beyond it
    EXPECT_NEAR(end_distance(tri, ray({0.5f, 0.5f, -2}, up, 3.125f, kInfinity)), 0.125, 1e-12);  // starts beyond
    EXPECT_NEAR(end_distance(tri, ray({0.5f, 0.5f, -2}, up, 0.0f, kInfinity)), 3.0, 1e-12);      // the nearer end
    // Distances, not parameters: a direction of length 4 crosses at t = 0.75.
    EXPECT_NEAR(end_distance(tri, ray({0.5f, 0.5f, -2}, {0, 0, 4}, 0.0f, 0.5f)), 1.0, 1e-12);
    // Behind the origin counts too (the line, not the ray): crossing at t = -1.
    EXPECT_NEAR(end_distance(tri, ray({0.5f, 0.5f, 2}, up, 0.0f, 1.0f)), 1.0, 1e-12);
    // The line misses the triangle, runs parallel to it, or the ray holds a NaN: infinitely far.
    EXPECT_EQ(end_distance(tri, ray({1.5f, 1.5f, -2}, up, 0.0f, 3.0f)), std::numeric_limits<double>::infinity());
    EXPECT_EQ(end_distance(tri, ray({0.5f, 0.5f, 1}, {1, 0, 0}, 0.0f, 3.0f)), std::numeric_limits<double>::infinity());
    EXPECT_EQ(end_distance(tri, ray({0.5f, 0.5f, -2}, {0, 0, std::nanf("")}, 0.0f, 3.0f)),
              std::numeric_limits<double>::infinity());
    // The brute force over the scene: crossings near an end, and on the segment away from the ends.
    const Ray ends_short = ray({0.5f, 0.5f, -2}, up, 0.0f, 2.99f);
    EXPECT_TRUE(end_crossings(s, ends_short, 0.011).near_end);
    EXPECT_FALSE(end_crossings(s, ends_short, 0.011).inside);
    EXPECT_FALSE(end_crossings(s, ends_short, 0.009).near_end);
    EXPECT_FALSE(end_crossings(s, ends_short, 0.009).inside);  // beyond tfar
    const Ray through = ray({0.5f, 0.5f, -2}, up, 0.0f, kInfinity);
    EXPECT_FALSE(end_crossings(s, through, 2.9).near_end);
    EXPECT_FALSE(end_crossings(s, through, 2.9).inside);  // not searched: nothing near an end
    EXPECT_TRUE(end_crossings(s, through, 3.1).near_end);
    EXPECT_FALSE(end_crossings(s, through, 3.1).inside);
    // The cube: the front face (z = -1, t = 3) on a segment that ends on the back face (t = 5).
    const Scene c = test::cube();
    const EndCrossings back = end_crossings(c, ray({0.1f, 0.2f, -4}, up, 0.0f, 4.99999f), 1e-4);
    EXPECT_TRUE(back.near_end);
    EXPECT_TRUE(back.inside);
    const EndCrossings past_front = end_crossings(c, ray({0.1f, 0.2f, -4}, up, 3.5f, 4.99999f), 1e-4);
    EXPECT_TRUE(past_front.near_end);
    EXPECT_FALSE(past_front.inside);
    const EndCrossings none = end_crossings(s, ray({1.5f, 1.5f, -2}, up, 0.0f, 3.0f), 1.0);
    EXPECT_FALSE(none.near_end || none.inside);
    const EndCrossings reversed = end_crossings(s, ray({0.5f, 0.5f, -2}, up, 4.0f, 2.0f), 10.0);
    EXPECT_FALSE(reversed.near_end || reversed.inside);
}

}  // namespace
}  // namespace beamtrace::oracle
