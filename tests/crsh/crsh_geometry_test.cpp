// The geometry of CRSH: bounding spheres hold their corners, Szecsi's cone growth (identical,
// antiparallel and wide directions), cone merging, keys, the radix sort, and the property everything
// rests on: the sphere-cone test never culls a triangle that a ray of the node hits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "common/triangle_reference.hpp"
#include "crsh/bounding_spheres.hpp"
#include "crsh/cone.hpp"
#include "crsh/radix_sort.hpp"
#include "crsh/ray_hierarchy.hpp"
#include "crsh/ray_keys.hpp"
#include "crsh/ray_node.hpp"

using namespace beamtrace;
using namespace beamtrace::crsh;

namespace {

Vec3d random_unit(std::mt19937& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    Vec3d v;
    do v = Vec3d(n(rng), n(rng), n(rng));
    while (length(v) < 1e-6);
    return unit(v);
}

// A unit direction within `angle` of the unit axis.
Vec3d near_direction(std::mt19937& rng, Vec3d axis, double angle) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const Vec3d side = unit(cross(axis, std::fabs(axis.x) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0)));
    const Vec3d up = cross(axis, side);
    const double a = angle * u(rng), phi = 2.0 * kPi * u(rng);
    return unit(axis * std::cos(a) + (side * std::cos(phi) + up * std::sin(phi)) * std::sin(a));
}

Float3 to_float(Vec3d v) { return {float(v.x), float(v.y), float(v.z)}; }

}  // namespace

TEST(CrshSpheres, TriangleSpheresHoldTheirCorners) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (float scale : {1e-6f, 1.0f, 1e4f})
        for (float offset : {0.0f, 1e3f, 1e7f})
            for (int i = 0; i < 2000; ++i) {
                Triangle t{{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
                for (Float3* p : {&t.v0, &t.v1, &t.v2}) *p = *p * scale + Float3{offset, -offset, offset};
                if (i % 3 == 0) t.v2 = (t.v0 + t.v1) * 0.5f + Float3{0, scale * 1e-3f, 0};  // obtuse, slivers
                if (i % 7 == 0) t.v2 = t.v1;                                                // degenerate
                ASSERT_TRUE(contains(triangle_sphere(t), t)) << i;
            }
}

TEST(CrshSpheres, TriangleSphereIsTheSmallestForAcuteAndObtuse) {
    const Triangle right{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};  // on the hypotenuse
    const Sphere s = triangle_sphere(right);
    EXPECT_FLOAT_EQ(s.centre.x, 1.0f);
    EXPECT_FLOAT_EQ(s.centre.y, 1.0f);
    EXPECT_NEAR(s.radius, std::sqrt(2.0f), 1e-6f);
    const Triangle obtuse{{0, 0, 0}, {4, 0, 0}, {2, 0.5f, 0}};  // on the long edge
    EXPECT_NEAR(triangle_sphere(obtuse).radius, 2.0f, 1e-6f);
    const float h = std::sqrt(3.0f);
    const Triangle equilateral{{-1, 0, 0}, {1, 0, 0}, {0, h, 0}};  // circumsphere
    EXPECT_NEAR(triangle_sphere(equilateral).radius, 2.0f / h, 1e-6f);
}

TEST(CrshSpheres, ObjectSpheresHoldEveryCorner) {
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(-5.0f, 5.0f);
    std::vector<Triangle> tris;
    for (int i = 0; i < 500; ++i)
        tris.push_back({{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}});
    const Sphere s = bounding_sphere(tris);
    for (const Triangle& t : tris) EXPECT_TRUE(contains(s, t));
}

TEST(CrshCones, IdenticalDirectionsLeaveTheConeAlone) {
    const Vec3d d = unit(Vec3d(0.3, -0.2, 0.9));
    Cone c = cone_of(d);
    for (int i = 0; i < 10; ++i) grow_cone(c, d);
    EXPECT_EQ(c.spread, 0.0);
    EXPECT_EQ(c.axis.x, d.x);
    EXPECT_FALSE(std::isnan(c.axis.x + c.axis.y + c.axis.z));
}

TEST(CrshCones, AntiparallelDirectionsMakeTheWholeSphere) {
    const Vec3d d = unit(Vec3d(1, 2, 3));
    Cone c = cone_of(d);
    grow_cone(c, d * -1.0);
    EXPECT_EQ(c.spread, kPi);
    EXPECT_TRUE(c.wide());
    EXPECT_FALSE(std::isnan(c.axis.x + c.axis.y + c.axis.z));
    // Nearly antiparallel: still a valid cone holding both.
    Cone n = cone_of(Vec3d(0, 0, 1));
    const Vec3d almost = unit(Vec3d(1e-9, 0, -1));
    grow_cone(n, almost);
    EXPECT_FALSE(std::isnan(n.spread));
    EXPECT_LE(angle_between(n.axis, almost), n.spread);
    EXPECT_LE(angle_between(n.axis, Vec3d(0, 0, 1)), n.spread);
}

TEST(CrshCones, DirectionsOverNinetyDegreesMakeAWideCone) {
    Cone c = cone_of(Vec3d(1, 0, 0));
    grow_cone(c, Vec3d(0, 1, 0));
    EXPECT_FALSE(c.wide());  // 90 degrees between them: a 45-degree cone
    EXPECT_NEAR(c.spread, kPi / 4, 1e-12);
    grow_cone(c, Vec3d(0, 0, 1));
    grow_cone(c, unit(Vec3d(-1, -1, 0)));
    EXPECT_TRUE(c.wide());
    RayNode node;
    node.cone = c;
    finish_node(node);
    EXPECT_TRUE(node.wide);
    EXPECT_TRUE(sphere_meets_node(node, -1e6, -1e6, -1e6, 0.0));  // a wide cone accepts everything
}

TEST(CrshCones, GrowthHoldsEveryDirectionAndNeverBeatsTheLargestAngle) {
    std::mt19937 rng(3);
    for (double spread : {1e-7, 1e-3, 0.2, 0.7, 1.5, 3.0})
        for (int trial = 0; trial < 300; ++trial) {
            const Vec3d axis = random_unit(rng);
            std::vector<Vec3d> dirs;
            for (int i = 0; i < 8; ++i) dirs.push_back(near_direction(rng, axis, spread));
            const Cone c = grow_cone(dirs);
            ASSERT_FALSE(std::isnan(c.spread));
            for (const Vec3d& d : dirs) ASSERT_LE(angle_between(c.axis, d), c.spread + 1e-12) << spread;
            // Szecsi's spread bounds the largest angle from its own axis (what the nodes keep).
            EXPECT_LE(largest_angle(c.axis, dirs), c.spread + 1e-12);
        }
}

TEST(CrshCones, MergedConesHoldTheirChildren) {
    std::mt19937 rng(4);
    for (double spread : {1e-4, 0.1, 0.5, 1.2})
        for (int trial = 0; trial < 300; ++trial) {
            const Vec3d axis = random_unit(rng);
            std::vector<Cone> children;
            std::vector<std::vector<Vec3d>> members;
            for (int k = 0; k < 8; ++k) {
                std::vector<Vec3d> dirs;
                const Vec3d a = near_direction(rng, axis, spread);
                for (int i = 0; i < 8; ++i) dirs.push_back(near_direction(rng, a, spread * 0.3));
                children.push_back(grow_cone(dirs));
                members.push_back(dirs);
            }
            const Cone m = merge_cones(children);
            for (const auto& dirs : members)
                for (const Vec3d& d : dirs) ASSERT_LE(angle_between(m.axis, d), m.spread + 1e-12);
        }
    // Axes that cancel out give the whole sphere.
    const Cone opposite[2] = {cone_of(Vec3d(0, 0, 1)), cone_of(Vec3d(0, 0, -1))};
    EXPECT_EQ(merge_cones(opposite).spread, kPi);
}

// The property of the whole method: for random nodes of every coherence (one origin or a cloud of
// them, directions within 1e-6 rad up to the whole sphere), levels 1 and 2, with and without the
// segment bound, and triangles placed on and around the rays, a triangle that some ray of the node
// hits is never culled.
TEST(CrshSphereCone, NeverCullsATriangleARayOfTheNodeHits) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::uniform_real_distribution<float> t01(0.0f, 1.0f);
    std::uint64_t hit_pairs = 0, culled = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const double spread = std::vector<double>{1e-6, 1e-3, 0.05, 0.4, 1.2, 1.7, 3.2}[trial % 7];
        const float cloud = std::vector<float>{0.0f, 1e-4f, 0.05f, 1.0f}[(trial / 7) % 4];
        const float far = trial % 11 == 0 ? 1e5f : 0.0f;
        const CrshKey key = trial % 2 ? CrshKey::end_point : CrshKey::origin;
        const Vec3d axis = random_unit(rng);
        const Float3 centre{far + u(rng), u(rng), u(rng)};
        // 8 children of 8 rays each: level-1 nodes, and their level-2 node.
        std::vector<Ray> rays;
        std::vector<RayNode> leaves;
        for (int k = 0; k < 8; ++k) {
            std::vector<BoundingRay> b;
            for (int i = 0; i < 8; ++i) {
                Ray r;
                r.org = centre + Float3{u(rng), u(rng), u(rng)} * cloud;
                r.dir = to_float(near_direction(rng, axis, spread)) * (0.5f + t01(rng));
                r.tnear = i % 3 == 0 ? -0.5f * t01(rng) : 0.1f * t01(rng);
                r.tfar = trial % 3 == 0 && i % 4 == 0 ? kInfinity : 1.0f + 5.0f * t01(rng);
                rays.push_back(r);
                b.push_back(bounding_ray(r, key));
            }
            leaves.push_back(leaf_node(b));
            leaves.back().first = std::uint32_t(8 * k);
            leaves.back().count = 8;
        }
        if (trial % 2) {  // half the trials without the segment bound (the paper's half-infinite cones)
            for (RayNode& n : leaves) n.length = std::numeric_limits<double>::infinity();
        }
        const RayNode top = merged_node(leaves);
        for (int j = 0; j < 60; ++j) {
            // A small triangle about a point of some ray's segment (or anywhere).
            const Ray& r = rays[std::size_t(rng() % rays.size())];
            const float hi = std::isfinite(r.tfar) ? r.tfar : 8.0f;
            const float t = r.tnear + (hi - r.tnear) * t01(rng);
            const float size = std::vector<float>{1e-5f, 1e-2f, 0.3f}[std::size_t(j % 3)];
            const Float3 p = j % 5 == 4 ? centre + Float3{u(rng), u(rng), u(rng)} * 5.0f : r.org + r.dir * t;
            const Triangle tri{p + Float3{u(rng), u(rng), u(rng)} * size, p + Float3{u(rng), u(rng), u(rng)} * size,
                               p + Float3{u(rng), u(rng), u(rng)} * size};
            const Sphere s = triangle_sphere(tri);
            for (std::size_t k = 0; k < leaves.size(); ++k) {
                bool hit = false;
                for (std::size_t i = 8 * k; i < 8 * k + 8 && !hit; ++i) {
                    TriangleHit h;
                    hit = intersect_triangle(make_watertight_ray(rays[i]), tri, h);
                }
                const bool keep = sphere_meets_node(leaves[k], s.centre.x, s.centre.y, s.centre.z, s.radius);
                culled += keep ? 0 : 1;
                if (!hit) continue;
                ++hit_pairs;
                ASSERT_TRUE(keep) << "trial " << trial << ", level-1 node " << k;
                ASSERT_TRUE(sphere_meets_node(top, s.centre.x, s.centre.y, s.centre.z, s.radius)) << "trial " << trial;
            }
        }
    }
    EXPECT_GT(hit_pairs, 1000u);
    EXPECT_GT(culled, 1000u);  // the test culls (it is not vacuous)
}

TEST(CrshSphereCone, SpheresOnTheSegmentsAreKeptAndFarOnesCulled) {
    // A narrow bundle along +z from about the origin.
    std::vector<BoundingRay> b;
    for (int i = 0; i < 8; ++i) b.push_back({Vec3d(0.01 * i, 0, 0), unit(Vec3d(0.001 * i, 0, 1))});
    RayNode node = leaf_node(b);
    EXPECT_FALSE(node.wide);
    EXPECT_TRUE(sphere_meets_node(node, 0.0, 0.0, 50.0, 0.0));     // on the axis, far ahead
    EXPECT_TRUE(sphere_meets_node(node, 0.0, 0.0, -0.001, 0.01));  // just behind the start, touching it
    EXPECT_FALSE(sphere_meets_node(node, 0.0, 0.0, -5.0, 1.0));    // behind the apex
    EXPECT_FALSE(sphere_meets_node(node, 10.0, 0.0, 1.0, 1.0));    // off to the side
}

namespace {
// The face coordinates' cells of a direction code (undoing the Morton interleave).
std::pair<int, int> face_cells(std::uint32_t code) {
    int u = 0, v = 0;
    for (int b = 0; b < kDirectionBits; ++b) {
        u |= int((code >> (2 * b + 1)) & 1u) << b;
        v |= int((code >> (2 * b)) & 1u) << b;
    }
    return {u, v};
}
}  // namespace

TEST(CrshKeys, DirectionCodesHaveNoSeamAtTheAzimuthWrap) {
    // Directions on both sides of phi = +-pi (where spherical coordinates jump from one end of their
    // range to the other) share a cube face and lie in neighbouring cells of it.
    const Vec3d a = unit(Vec3d(-1, 1e-4, 0.1)), b = unit(Vec3d(-1, -1e-4, 0.1));
    const std::uint32_t ca = direction_code(a), cb = direction_code(b);
    EXPECT_EQ(ca >> (2 * kDirectionBits), cb >> (2 * kDirectionBits));
    const auto [ua, va] = face_cells(ca);
    const auto [ub, vb] = face_cells(cb);
    EXPECT_LE(std::abs(ua - ub) + std::abs(va - vb), 2);
    for (int f = 0; f < 6; ++f) {
        Vec3d d(0.1, -0.2, 0.05);
        (f / 2 == 0 ? d.x : f / 2 == 1 ? d.y : d.z) = f % 2 ? -1.0 : 1.0;
        EXPECT_EQ(direction_code(unit(d)) >> (2 * kDirectionBits), std::uint32_t(f));
    }
}

TEST(CrshSphereCone, TheSegmentBoundCullsBeyondTheLongestSegmentEvenForWideCones) {
    std::vector<BoundingRay> b;
    for (int i = 0; i < 8; ++i) {
        const double a = 2.0 * kPi * i / 8;
        b.push_back({Vec3d(0, 0, 0), Vec3d(std::cos(a), std::sin(a), 0), 2.0});  // a fan: a wide cone
    }
    RayNode node = leaf_node(b);
    EXPECT_TRUE(node.wide);
    EXPECT_GE(node.length, 2.0);
    EXPECT_TRUE(sphere_meets_node(node, 2.5, 0.0, 0.0, 0.6));
    EXPECT_FALSE(sphere_meets_node(node, 2.5, 0.0, 0.0, 0.4));
    node.length = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(sphere_meets_node(node, 2.5, 0.0, 0.0, 0.4));
}

TEST(CrshKeys, EndPointKeysBoundShadowRaysFromTheLight) {
    const Ray r{{1, 2, 3}, 0.0f, {4, -2, 1}, 1.0f};
    const BoundingRay o = bounding_ray(r, CrshKey::origin), e = bounding_ray(r, CrshKey::end_point);
    EXPECT_EQ(o.start.x, 1.0);
    EXPECT_EQ(e.start.x, 5.0);
    EXPECT_EQ(e.start.y, 0.0);
    EXPECT_NEAR(dot(e.dir, o.dir), -1.0, 1e-15);
    Ray infinite = r;
    infinite.tfar = kInfinity;
    EXPECT_EQ(bounding_ray(infinite, CrshKey::end_point).start.x, 1.0);  // no end: bounded from the origin
}

TEST(CrshRadixSort, SortsStablyLikeStdStableSort) {
    std::mt19937_64 rng(6);
    for (std::size_t n : {0u, 1u, 2u, 100u, 5000u}) {
        std::vector<std::uint64_t> keys(n);
        for (auto& k : keys) k = (rng() >> (rng() % 64)) & (n % 2 ? 0xFFFF0000FFull : ~0ull);
        for (std::size_t i = 0; i + 1 < n; i += 7) keys[i + 1] = keys[i];  // duplicates
        std::vector<std::uint32_t> values(n);
        std::iota(values.begin(), values.end(), 0u);
        std::vector<std::uint32_t> want = values;
        std::stable_sort(want.begin(), want.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
        std::vector<std::uint64_t> sorted = keys;
        radix_sort(sorted, values);
        EXPECT_EQ(values, want);
        for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(sorted[i], keys[want[i]]);
    }
}
