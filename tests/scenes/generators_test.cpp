// The procedural scenes: sizes, closedness, determinism, parameter checks, default cameras.
#include "scenes/generators.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>

#include "beamtrace/error.hpp"
#include "mesh_topology.hpp"
#include "scenes/desk_objects.hpp"

namespace beamtrace::scenes {
namespace {

using testing::topology;

bool same_geometry(const Scene& a, const Scene& b) {
    return std::ranges::equal(a.vertices(), b.vertices()) && std::ranges::equal(a.indices(), b.indices());
}

bool inside(const Box& box, Float3 p) {
    return p.x >= box.lower.x && p.y >= box.lower.y && p.z >= box.lower.z && p.x <= box.upper.x && p.y <= box.upper.y &&
           p.z <= box.upper.z;
}

// --- tetra ---

TEST(SierpinskiTetra, CountsAreExact) {
    for (int level = 0; level <= 6; ++level) {
        const SceneSource s = sierpinski_tetra(level);
        const std::size_t tetrahedra = std::size_t{1} << (2 * level);
        EXPECT_EQ(s.scene.triangle_count(), 4 * tetrahedra) << "level " << level;
        EXPECT_EQ(s.scene.vertex_count(), 4 * tetrahedra);
        EXPECT_EQ(s.scene.degenerate_count(), 0u);
        EXPECT_EQ(s.name, "tetra:" + std::to_string(level));
    }
}

TEST(SierpinskiTetra, EveryTetrahedronIsClosedAndVolumeHalvesPerLevel) {
    const SceneSource base = sierpinski_tetra(0);
    const double base_volume = topology(base.scene.vertices(), base.scene.indices()).signed_volume;
    EXPECT_NEAR(base_volume, 8.0 / (6.0 * std::sqrt(2.0)), 1e-5);  // regular tetrahedron of edge 2
    for (int level = 1; level <= 5; ++level) {
        const SceneSource s = sierpinski_tetra(level);
        const auto t = topology(s.scene.vertices(), s.scene.indices());
        EXPECT_TRUE(t.closed()) << "level " << level << ": " << t.edges_not_shared_by_two << " open edges";
        EXPECT_EQ(t.edges, 6u << (2 * level));
        EXPECT_NEAR(t.signed_volume, base_volume / (1 << level), 1e-5);
    }
}

TEST(SierpinskiTetra, TouchingCornersAreBitIdentical) {
    // Level L has 2 * 4^L + 2 distinct corner positions: the 4 outer corners belong to one
    // tetrahedron, every other point to exactly two. Any rounding difference would add positions.
    for (int level = 1; level <= 4; ++level) {
        const SceneSource s = sierpinski_tetra(level);
        std::map<std::tuple<float, float, float>, int> uses;
        for (const Float3& p : s.scene.vertices()) ++uses[{p.x, p.y, p.z}];
        EXPECT_EQ(uses.size(), 2 * (std::size_t{1} << (2 * level)) + 2) << "level " << level;
        for (const auto& [p, n] : uses) EXPECT_LE(n, 2);
    }
}

TEST(SierpinskiTetra, StandsOnTheFloorAndIsFramed) {
    const SceneSource s = sierpinski_tetra(3);
    EXPECT_NEAR(s.scene.bounds().lower.y, 0.0f, 1e-6f);
    EXPECT_NEAR(s.scene.bounds().upper.y, 2.0f * std::sqrt(2.0f / 3.0f), 1e-5f);
    EXPECT_FALSE(inside(s.scene.bounds(), s.camera.eye));
    EXPECT_EQ(s.camera.at, s.scene.bounds().center());
}

TEST(SierpinskiTetra, RejectsLevelsOutOfRange) {
    for (int level : {-1, 11}) {
        try {
            sierpinski_tetra(level);
            ADD_FAILURE() << "level " << level << " accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("between 0 and 10"), std::string::npos) << e.what();
        }
    }
}

// --- sphereflake ---

TEST(Sphereflake, CountsPerLevel) {
    const std::size_t expected[] = {1280, 1280 + 9 * 320, 1280 + 90 * 320, 1280 + 819 * 320};
    for (int level = 0; level <= 3; ++level) {
        const SceneSource s = sphereflake(level);
        EXPECT_EQ(s.scene.triangle_count(), expected[level]) << "level " << level;
        EXPECT_EQ(s.name, "sphereflake:" + std::to_string(level));
    }
}

TEST(Sphereflake, SpheresAreClosedAndChildrenTouchTheirParent) {
    const SceneSource s = sphereflake(2);
    const auto t = topology(s.scene.vertices(), s.scene.indices());
    EXPECT_TRUE(t.closed()) << t.edges_not_shared_by_two << " open edges, " << t.directed_edges_repeated << " flipped";
    EXPECT_GT(t.signed_volume, 0.0);
    EXPECT_LT(t.signed_volume, 4.0 / 3.0 * std::acos(-1.0) * (1.0 + 9.0 / 27 + 81.0 / 729));
    // The root is the unit sphere; the flake reaches at most 1 + 2/3 + 2/9 from its centre.
    const Box b = s.scene.bounds();
    EXPECT_NEAR(b.lower.y, -1.0f, 1e-5f);  // nothing grows below the equator of the root
    for (int a = 0; a < 3; ++a) EXPECT_LE(std::max(-b.lower[a], b.upper[a]), 1.0f + 2.0f / 3 + 2.0f / 9 + 1e-5f);
    // Root vertices (the first 642) on the unit sphere; the next sphere is a child of radius 1/3
    // centred 4/3 from the origin.
    for (std::size_t i = 0; i < 642; ++i) EXPECT_NEAR(length(s.scene.vertices()[i]), 1.0f, 1e-6f);
    Float3 centre{0, 0, 0};
    for (std::size_t i = 642; i < 642 + 162; ++i) centre = centre + s.scene.vertices()[i] * (1.0f / 162);
    EXPECT_NEAR(length(centre), 4.0f / 3.0f, 1e-4f);
}

TEST(Sphereflake, RejectsLevelsOutOfRange) {
    EXPECT_THROW(sphereflake(-1), Error);
    EXPECT_THROW(sphereflake(6), Error);
}

// --- random ---

TEST(RandomTriangles, CountBoundsAndSize) {
    const SceneSource s = random_triangles(5000);
    EXPECT_EQ(s.scene.triangle_count(), 5000u);
    EXPECT_EQ(s.name, "random:5000");
    const Box unit{{0, 0, 0}, {1, 1, 1}};
    const float h = random_triangle_half_size(5000);
    for (const Triangle& t : s.scene.triangles()) {
        for (Float3 p : {t.v0, t.v1, t.v2}) ASSERT_TRUE(inside(unit, p));
        EXPECT_LE(length(t.v1 - t.v0), 2.0f * std::sqrt(3.0f) * h * 1.0001f);  // small: corners within +-h of a centre
    }
    // Spread through the whole cube.
    EXPECT_LT(s.scene.bounds().lower.x, 0.02f);
    EXPECT_GT(s.scene.bounds().upper.z, 0.98f);
    EXPECT_FALSE(inside(s.scene.bounds(), s.camera.eye));
}

TEST(RandomTriangles, DeterministicAndSeeded) {
    EXPECT_TRUE(same_geometry(random_triangles(1000).scene, random_triangles(1000).scene));
    EXPECT_FALSE(same_geometry(random_triangles(1000, 1).scene, random_triangles(1000, 2).scene));
    // The triangle size follows N, so even the first triangle differs between N = 10 and N = 20.
    const SceneSource small = random_triangles(10), large = random_triangles(20);
    EXPECT_NE(small.scene.triangle(0).v0, large.scene.triangle(0).v0);
    EXPECT_THROW(random_triangles(0), Error);
    EXPECT_THROW(random_triangles(kMaxRandomTriangles + 1), Error);
}

// --- desk objects and the room ---

TEST(DeskObjects, ClosedInsideTheirFootprintAndOfFixedSize) {
    for (int k = 0; k < kDeskObjectKinds; ++k) {
        const auto kind = static_cast<DeskObject>(k);
        MeshBuilder m;
        const Float3 base{3, 0.76f, -2};
        const std::size_t n = add_desk_object(m, kind, base, 0.12f, 0.7f);
        EXPECT_EQ(n, desk_object_triangles(kind));
        EXPECT_GE(n, 14000u) << desk_object_name(kind);
        EXPECT_LE(n, 16000u) << desk_object_name(kind);
        const auto t = topology(m.vertices(), m.indices());
        EXPECT_TRUE(t.closed()) << desk_object_name(kind);
        EXPECT_GT(t.signed_volume, 0.0) << desk_object_name(kind);
        float lowest = 1e9f, widest = 0.0f;
        for (const Float3& p : m.vertices()) {
            lowest = std::min(lowest, p.y);
            widest = std::max(widest, std::hypot(p.x - base.x, p.z - base.z));
        }
        EXPECT_GE(lowest, base.y - 1e-5f) << desk_object_name(kind) << " sinks into the desk";
        EXPECT_LT(lowest, base.y + 0.02f) << desk_object_name(kind) << " floats above the desk";
        EXPECT_LE(widest, 0.12f * 1.001f) << desk_object_name(kind) << " leaves its footprint";
    }
}

TEST(Room, AboutAMillionClosedTrianglesThatDependOnTheSeed) {
    const SceneSource a = room(1);
    EXPECT_EQ(a.name, "room:1");
    EXPECT_GE(a.scene.triangle_count(), 900'000u);
    EXPECT_LE(a.scene.triangle_count(), 1'200'000u);
    const auto t = topology(a.scene.vertices(), a.scene.indices());
    EXPECT_TRUE(t.closed()) << t.edges_not_shared_by_two << " open edges";
    // The shell faces inward (negative volume), so the total is the furniture minus the room.
    EXPECT_LT(t.signed_volume, 0.0);
    EXPECT_GT(t.signed_volume, -12.0 * 3.2 * 9.0);

    const SceneSource b = room(2);
    EXPECT_GE(b.scene.triangle_count(), 900'000u);
    EXPECT_LE(b.scene.triangle_count(), 1'200'000u);
    EXPECT_FALSE(same_geometry(a.scene, b.scene));
    EXPECT_TRUE(same_geometry(a.scene, room(1).scene));
}

TEST(Room, ShellBoundsEverythingAndCameraStandsInside) {
    const SceneSource s = room();
    const Box b = s.scene.bounds();
    EXPECT_EQ(b.lower, (Float3{0, 0, 0}));
    EXPECT_EQ(b.upper, (Float3{12, 3.2f, 9}));
    EXPECT_TRUE(inside(b, s.camera.eye));
    EXPECT_TRUE(inside(b, s.camera.at));
    EXPECT_GT(s.camera.eye.y, 1.4f);  // standing eye height
    EXPECT_LT(s.camera.eye.y, 2.0f);
    EXPECT_LT(s.camera.eye.x, 1.0f);  // near a wall
    EXPECT_GT(s.camera.eye.z, 8.0f);
    EXPECT_LT(s.camera.at.y, s.camera.eye.y);  // looking across the desks, slightly down
}

}  // namespace
}  // namespace beamtrace::scenes
