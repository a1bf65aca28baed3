// MeshBuilder's primitives are closed, outward-facing and of the promised size.
#include "scenes/mesh_builder.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "beamtrace/error.hpp"
#include "mesh_topology.hpp"

namespace beamtrace::scenes {
namespace {

using testing::topology;
constexpr double kPi = std::numbers::pi;

TEST(MeshBuilder, BoxIsClosedAndFacesOutwardOrInward) {
    MeshBuilder m;
    m.add_box(Box{{1, 2, 3}, {2, 4, 7}});
    EXPECT_EQ(m.vertex_count(), 8u);
    EXPECT_EQ(m.triangle_count(), 12u);
    const auto t = topology(m.vertices(), m.indices());
    EXPECT_TRUE(t.closed());
    EXPECT_EQ(t.edges, 18u);
    EXPECT_NEAR(t.signed_volume, 8.0, 1e-9);

    MeshBuilder shell;
    shell.add_box(Box{{0, 0, 0}, {2, 3, 4}}, Facing::inward);
    const auto s = topology(shell.vertices(), shell.indices());
    EXPECT_TRUE(s.closed());
    EXPECT_NEAR(s.signed_volume, -24.0, 1e-9);
}

TEST(MeshBuilder, TetrahedronFacesAwayFromOppositeCorner) {
    for (bool mirrored : {false, true}) {
        MeshBuilder m;
        const Float3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0}, d{0, 0, 1};
        if (mirrored)
            m.add_tetrahedron(a, c, b, d);
        else
            m.add_tetrahedron(a, b, c, d);
        const auto t = topology(m.vertices(), m.indices());
        EXPECT_TRUE(t.closed());
        EXPECT_NEAR(t.signed_volume, 1.0 / 6.0, 1e-7);
    }
}

TEST(MeshBuilder, IcosphereIsAClosedUnitSphere) {
    for (int s = 0; s <= 4; ++s) {
        const MeshBuilder m = unit_icosphere(s);
        const std::size_t faces = 20u << (2 * s);
        EXPECT_EQ(m.triangle_count(), faces);
        EXPECT_EQ(m.vertex_count(), faces / 2 + 2);  // Euler: V - E + F = 2 with E = 3F/2
        for (const Float3& p : m.vertices()) EXPECT_NEAR(length(p), 1.0f, 1e-6f);
        const auto t = topology(m.vertices(), m.indices());
        EXPECT_TRUE(t.closed()) << "subdivisions " << s;
        EXPECT_GT(t.signed_volume, 0.0);
        EXPECT_LT(t.signed_volume, 4.0 / 3.0 * kPi);  // inscribed
    }
    const MeshBuilder fine = unit_icosphere(4);
    EXPECT_NEAR(topology(fine.vertices(), fine.indices()).signed_volume, 4.0 / 3.0 * kPi, 0.02);
    EXPECT_THROW(unit_icosphere(-1), Error);
    EXPECT_THROW(unit_icosphere(9), Error);
}

TEST(MeshBuilder, TessellatedSphereIsPlacedAndScaled) {
    MeshBuilder m;
    m.add_tessellated_sphere({1, 2, 3}, 0.5f, 2);
    EXPECT_EQ(m.triangle_count(), 320u);
    for (const Float3& p : m.vertices()) EXPECT_NEAR(length(p - Float3{1, 2, 3}), 0.5f, 1e-6f);
    EXPECT_TRUE(topology(m.vertices(), m.indices()).closed());
}

TEST(MeshBuilder, LatheIsClosedWithTheStatedCount) {
    MeshBuilder m;
    const std::vector<ProfilePoint> cylinder{{0, 0}, {1, 0}, {1, 0.5f}, {1, 2}, {0, 2}};
    m.add_lathe(Frame{}, cylinder, 64);
    EXPECT_EQ(m.triangle_count(), 2u * 64 * 3);
    EXPECT_EQ(m.vertex_count(), 2u + 64 * 3);
    const auto t = topology(m.vertices(), m.indices());
    EXPECT_TRUE(t.closed());
    const double polygon_area = 0.5 * 64 * std::sin(2 * kPi / 64);  // inscribed 64-gon of radius 1
    EXPECT_NEAR(t.signed_volume, 2.0 * polygon_area, 1e-4);

    EXPECT_THROW(m.add_lathe(Frame{}, std::vector<ProfilePoint>{{1, 0}, {1, 1}, {0, 1}}, 8), Error);  // open bottom
    EXPECT_THROW(m.add_lathe(Frame{}, std::vector<ProfilePoint>{{0, 0}, {0, 1}, {0, 2}}, 8), Error);  // all on axis
    EXPECT_THROW(m.add_lathe(Frame{}, cylinder, 2), Error);
}

TEST(MeshBuilder, UvSphereAndEllipsoid) {
    MeshBuilder m;
    m.add_uv_sphere(Frame::upright({0, 0, 0}, 0.3f, 2.0f).scaled(1.0f, 0.5f, 1.0f), 96, 48);
    EXPECT_EQ(m.triangle_count(), 2u * 96 * 47);
    const auto t = topology(m.vertices(), m.indices());
    EXPECT_TRUE(t.closed());
    EXPECT_NEAR(t.signed_volume, 4.0 / 3.0 * kPi * 2 * 1 * 2, 0.2);  // semi-axes 2, 1, 2 (inscribed: a little less)
}

TEST(MeshBuilder, TorusIsClosedWithItsVolume) {
    MeshBuilder m;
    m.add_torus(Frame::along({1, 1, 1}, {1, 2, 3}), 2.0f, 0.5f, 200, 60);
    EXPECT_EQ(m.triangle_count(), 2u * 200 * 60);
    EXPECT_EQ(m.vertex_count(), 200u * 60);
    const auto t = topology(m.vertices(), m.indices());
    EXPECT_TRUE(t.closed());
    EXPECT_NEAR(t.signed_volume, 2 * kPi * kPi * 2.0 * 0.25, 0.05);
    // Every vertex lies on the tube around the circle of radius 2 about the axis.
    const Frame f = Frame::along({1, 1, 1}, {1, 2, 3});
    for (const Float3& p : m.vertices()) {
        const Float3 q = p - f.origin;
        const float along = dot(q, f.y);
        const float across = length(q - f.y * along);
        EXPECT_NEAR(std::hypot(across - 2.0f, along), 0.5f, 1e-4f);
    }
}

TEST(MeshBuilder, TubeAlongAKnotIsClosedAndFacesOutward) {
    std::vector<Float3> knot;
    for (int k = 0; k < 240; ++k) {
        const float t = 2.0f * std::numbers::pi_v<float> * k / 240;
        knot.push_back({std::sin(t) + 2 * std::sin(2 * t), std::cos(t) - 2 * std::cos(2 * t), -std::sin(3 * t)});
    }
    MeshBuilder m;
    m.add_tube(Frame{}, knot, 0.3f, 20);
    EXPECT_EQ(m.triangle_count(), 2u * 240 * 20);
    const auto t = topology(m.vertices(), m.indices());
    EXPECT_TRUE(t.closed());
    EXPECT_GT(t.signed_volume, 0.0);
    // The transported frames close up: the last ring joins the first without a twist, so matching
    // vertices of neighbouring rings are as close across the seam as anywhere else.
    auto step = [&](std::size_t ring) {
        float longest = 0.0f;
        for (std::size_t j = 0; j < 20; ++j)
            longest =
                std::max(longest, length(m.vertices()[((ring + 1) % 240) * 20 + j] - m.vertices()[ring * 20 + j]));
        return longest;
    };
    float longest_inside = 0.0f;
    for (std::size_t ring = 0; ring + 1 < 240; ++ring) longest_inside = std::max(longest_inside, step(ring));
    EXPECT_LE(step(239), 1.1f * longest_inside);
    EXPECT_THROW(m.add_tube(Frame{}, std::span<const Float3>(knot).first(2), 0.3f, 20), Error);
}

TEST(MeshBuilder, AppendPlacesACopy) {
    const MeshBuilder unit = unit_icosphere(1);
    MeshBuilder m;
    m.add_box(Box{{0, 0, 0}, {1, 1, 1}});
    m.append(unit, Frame::upright({5, 0, 0}, 1.0f, 2.0f));
    EXPECT_EQ(m.triangle_count(), 12u + 80u);
    EXPECT_EQ(m.vertex_count(), 8u + unit.vertex_count());
    for (std::size_t i = 8; i < m.vertex_count(); ++i)
        EXPECT_NEAR(length(m.vertices()[i] - Float3{5, 0, 0}), 2.0f, 1e-5f);
    for (std::size_t i = 36; i < m.indices().size(); ++i) EXPECT_GE(m.indices()[i], 8u);
    EXPECT_TRUE(topology(m.vertices(), m.indices()).closed());
}

TEST(MeshBuilder, SoupTrianglesAndBuild) {
    MeshBuilder m;
    m.add_triangle(Float3{0, 0, 0}, Float3{1, 0, 0}, Float3{0, 1, 0});
    m.add_triangle(Float3{0, 0, 1}, Float3{1, 0, 1}, Float3{0, 1, 1});
    EXPECT_EQ(m.vertex_count(), 6u);
    const Scene s = m.build();
    EXPECT_EQ(s.triangle_count(), 2u);
    EXPECT_EQ(s.triangle(1).v0, (Float3{0, 0, 1}));
    EXPECT_THROW(MeshBuilder{}.build(), Error);  // an empty scene
}

TEST(Frame, UprightTurnsAboutVerticalAndComposes) {
    const Frame f = Frame::upright({1, 0, 0}, std::numbers::pi_v<float> / 2, 2.0f);
    const Float3 p = f.point({1, 1, 0});  // +x turned a quarter about +y goes to -z
    EXPECT_NEAR(p.x, 1.0f, 1e-6f);
    EXPECT_NEAR(p.y, 2.0f, 1e-6f);
    EXPECT_NEAR(p.z, -2.0f, 1e-6f);
    const Frame g = f * Frame::upright({0, 1, 0});
    const Float3 q = g.point({0, 0, 0});
    EXPECT_NEAR(q.y, 2.0f, 1e-6f);
    const Frame a = Frame::along({0, 0, 0}, {0, 0, 5});
    EXPECT_NEAR(dot(a.y, Float3{0, 0, 1}), 1.0f, 1e-6f);
    EXPECT_NEAR(dot(cross(a.x, a.y), a.z), 1.0f, 1e-6f);  // right-handed
}

}  // namespace
}  // namespace beamtrace::scenes
