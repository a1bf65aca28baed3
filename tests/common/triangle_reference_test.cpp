// The scalar watertight test against hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>

#include "common/triangle_reference.hpp"

using namespace beamtrace;

namespace {
const Triangle kTri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

bool shoot(Float3 org, Float3 dir, TriangleHit& h, float tnear = 0, float tfar = kInfinity) {
    return intersect_triangle(make_watertight_ray(Ray{org, tnear, dir, tfar}), kTri, h);
}
}  // namespace

TEST(TriangleReference, HitsWithEmbreeBarycentrics) {
    TriangleHit h{};
    ASSERT_TRUE(shoot({0.25f, 0.5f, 2}, {0, 0, -1}, h));
    EXPECT_FLOAT_EQ(h.t, 2.0f);
    EXPECT_FLOAT_EQ(h.u, 0.25f);                          // weight of v1 = x
    EXPECT_FLOAT_EQ(h.v, 0.5f);                           // weight of v2 = y
    ASSERT_TRUE(shoot({0.25f, 0.5f, -3}, {0, 0, 2}, h));  // from behind, unnormalised direction
    EXPECT_FLOAT_EQ(h.t, 1.5f);
}

TEST(TriangleReference, Misses) {
    TriangleHit h{};
    EXPECT_FALSE(shoot({0.75f, 0.75f, 1}, {0, 0, -1}, h));  // outside the hypotenuse
    EXPECT_FALSE(shoot({0.25f, 0.25f, 1}, {0, 0, 1}, h));   // pointing away
    EXPECT_FALSE(shoot({0.25f, 0.25f, 1}, {1, 0, 0}, h));   // parallel to the plane
}

TEST(TriangleReference, IntervalIsInclusive) {
    TriangleHit h{};
    EXPECT_TRUE(shoot({0.25f, 0.25f, 1}, {0, 0, -1}, h, 0.0f, 1.0f));
    EXPECT_TRUE(shoot({0.25f, 0.25f, 1}, {0, 0, -1}, h, 1.0f, 1.0f));
    EXPECT_FALSE(shoot({0.25f, 0.25f, 1}, {0, 0, -1}, h, 0.0f, 0.999f));
    EXPECT_FALSE(shoot({0.25f, 0.25f, 1}, {0, 0, -1}, h, 1.001f, 5.0f));
}

TEST(TriangleReference, EdgesAndCornersAreHit) {
    TriangleHit h{};
    EXPECT_TRUE(shoot({0, 0, 1}, {0, 0, -1}, h));        // corner v0
    EXPECT_TRUE(shoot({1, 0, 1}, {0, 0, -1}, h));        // corner v1
    EXPECT_TRUE(shoot({0.5f, 0, 1}, {0, 0, -1}, h));     // edge v0-v1
    EXPECT_TRUE(shoot({0.5f, 0.5f, 1}, {0, 0, -1}, h));  // hypotenuse
}

TEST(TriangleReference, SharedEdgeIsWatertight) {
    // Two triangles sharing the diagonal of a quad; rays along the diagonal hit at least one.
    const Triangle a{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, b{{0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (int i = 0; i <= 1000; ++i) {
        const float s = float(i) / 1000.0f;
        const float dx = 0.0003f * float(i % 7), dy = -0.0002f * float(i % 5);
        // Passes through (s, s, 0) on the shared edge at t = 1.
        const WatertightRay w = make_watertight_ray(Ray{{s + dx, s + dy, 1.0f}, 0.0f, {-dx, -dy, -1.0f}, kInfinity});
        TriangleHit h{};
        EXPECT_TRUE(intersect_triangle(w, a, h) || intersect_triangle(w, b, h)) << "leak at s=" << s;
    }
}

TEST(TriangleReference, DegenerateNeverHit) {
    const Triangle line{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    TriangleHit h{};
    EXPECT_FALSE(intersect_triangle(make_watertight_ray(Ray{{0.5f, 0, 1}, 0, {0, 0, -1}, kInfinity}), line, h));
}

TEST(TriangleReference, AxisDirectionsWithNegativeZero) {
    TriangleHit h{};
    EXPECT_TRUE(shoot({0.25f, 0.25f, 1}, {-0.0f, 0.0f, -1}, h));
    EXPECT_FLOAT_EQ(h.t, 1.0f);
    EXPECT_TRUE(shoot({0.25f, 0.25f, 1}, {0.0f, -0.0f, -1}, h));
    EXPECT_FLOAT_EQ(h.t, 1.0f);
}
