// The geometry candidate sets rest on: a cell's beam (nine half-spaces) and a light buffer's
// direction rectangles (and the grid cells they are placed in) never reject a triangle that a ray classified into the cell hits, and they do
// reject triangles well outside (or the sets would be the whole scene).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/triangle_reference.hpp"
#include "raycls/candidate_list.hpp"
#include "raycls/direction_grid.hpp"
#include "raycls/cell_beam.hpp"
#include "raycls/ray_space.hpp"

using namespace beamtrace;
using namespace beamtrace::raycls;

namespace {

// A random cell: a box inside [-4, 4]^3, a face, a random dyadic (u, v) rectangle of depth 0..6.
CellBounds random_cell(std::mt19937& rng) {
    std::uniform_real_distribution<float> x(-4.0f, 4.0f), w(0.0f, 2.0f);
    CellBounds c;
    for (int k = 0; k < 3; ++k) {
        c.lo[k] = x(rng);
        c.hi[k] = c.lo[k] + w(rng) * (rng() % 4 == 0 ? 0.0f : 1.0f);  // some boxes are points
    }
    c.face = int(rng() % 6);
    const int depth = int(rng() % 7);
    for (int d = 0; d < depth; ++d) c = child_bounds(c, int(rng() % 4), false);
    return c;
}

// A ray classified into the cell: origin in the box, direction code in the rectangle.
Ray ray_in(const CellBounds& c, std::mt19937& rng) {
    std::uniform_real_distribution<float> t(0.0f, 1.0f);
    Ray r;
    for (int k = 0; k < 3; ++k) r.org[k] = c.lo[k] + t(rng) * (c.hi[k] - c.lo[k]);
    const float u = c.u0 + t(rng) * (c.u1 - c.u0), v = c.v0 + t(rng) * (c.v1 - c.v0);
    r.dir[face_axis(c.face)] = float(face_sign(c.face));
    r.dir[face_a(c.face)] = u;
    r.dir[face_b(c.face)] = v;
    return r;
}

// A small triangle around the point at parameter t of the ray.
Triangle triangle_around(const Ray& r, float t, std::mt19937& rng) {
    std::uniform_real_distribution<float> d(-0.05f, 0.05f);
    const Float3 p = r.org + r.dir * t;
    Triangle tri;
    for (;;) {
        tri.v0 = p + Float3{d(rng), d(rng), d(rng)};
        tri.v1 = p + Float3{d(rng), d(rng), d(rng)};
        tri.v2 = p + Float3{d(rng), d(rng), d(rng)};
        TriangleHit h;
        if (intersect_triangle(make_watertight_ray(r), tri, h)) return tri;
    }
}

}  // namespace

TEST(CellBeam, NeverRejectsATriangleARayOfTheCellHits) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> t(0.0f, 30.0f);
    int tested = 0;
    for (int i = 0; i < 4000; ++i) {
        const CellBounds c = random_cell(rng);
        const CellBeam beam = make_cell_beam(c, 1e-5, 1e-6);
        const Ray r = ray_in(c, rng);
        const DirectionCode code = direction_code(r.dir);
        if (code.face != c.face) continue;  // |u| or |v| = 1 may pick another face: not this cell's ray
        const Triangle tri = triangle_around(r, t(rng), rng);
        ASSERT_TRUE(may_meet_triangle(beam, tri)) << "cell " << i;
        Box box;
        box.extend(tri.v0);
        box.extend(tri.v1);
        box.extend(tri.v2);
        ASSERT_NE(box_side(beam, box), BoxSide::outside) << "cell " << i;
        ++tested;
    }
    EXPECT_GT(tested, 3000);
}

TEST(CellBeam, RejectsTrianglesBehindAndBeside) {
    CellBounds c;
    for (int k = 0; k < 3; ++k) c.lo[k] = 0.0f, c.hi[k] = 1.0f;
    c.face = 4;  // +z
    c.u0 = 0.0f, c.u1 = 0.25f, c.v0 = 0.0f, c.v1 = 0.25f;
    const CellBeam beam = make_cell_beam(c, 1e-5, 1e-6);
    const Triangle behind{{0.5f, 0.5f, -1.0f}, {0.6f, 0.5f, -1.0f}, {0.5f, 0.6f, -1.0f}};
    const Triangle beside{{-3.0f, 0.5f, 2.0f}, {-2.9f, 0.5f, 2.0f}, {-3.0f, 0.6f, 2.0f}};
    const Triangle ahead{{0.5f, 0.5f, 3.0f}, {0.6f, 0.5f, 3.0f}, {0.5f, 0.6f, 3.0f}};
    EXPECT_FALSE(may_meet_triangle(beam, behind));
    EXPECT_FALSE(may_meet_triangle(beam, beside));
    EXPECT_TRUE(may_meet_triangle(beam, ahead));
    Box far_inside;  // well inside the beam, far ahead
    far_inside.extend(Float3{2.0f, 2.0f, 20.0f});
    far_inside.extend(Float3{2.2f, 2.2f, 20.5f});
    EXPECT_EQ(box_side(beam, far_inside), BoxSide::inside);
    Box straddling;
    straddling.extend(Float3{0.5f, 0.5f, -1.0f});
    straddling.extend(Float3{0.6f, 0.6f, 3.0f});
    EXPECT_EQ(box_side(beam, straddling), BoxSide::partly);
    Box behind_box;
    behind_box.extend(behind.v0);
    behind_box.extend(behind.v1);
    behind_box.extend(behind.v2);
    EXPECT_EQ(box_side(beam, behind_box), BoxSide::outside);
}

TEST(DirectionRects, HoldTheDirectionOfEveryRayFromTheApexThatHits) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> t(0.1f, 20.0f), small(0.0f, 0.01f);
    int tested = 0;
    for (int i = 0; i < 3000; ++i) {
        CellBounds c = random_cell(rng);
        for (int k = 0; k < 3; ++k) c.hi[k] = c.lo[k] + small(rng);  // a light buffer's tiny apex box
        Box apex;
        apex.lower = Float3{c.lo[0], c.lo[1], c.lo[2]};
        apex.upper = Float3{c.hi[0], c.hi[1], c.hi[2]};
        const Ray r = ray_in(c, rng);
        const DirectionCode code = direction_code(r.dir);
        if (code.face != c.face) continue;
        const Triangle tri = triangle_around(r, t(rng), rng);
        const Float3 corners[3] = {tri.v0, tri.v1, tri.v2};
        const std::uint32_t indices[3] = {0, 1, 2};
        const Scene scene(corners, indices);
        CandidateList list;
        list.items.push_back(Candidate{tri, 0.0f, 0});
        add_direction_rects(list, apex, c.face, 1e-6);
        const DirectionRect& rect = list.rect_items[0].rect;
        ASSERT_LE(rect.u0, code.u) << i;
        ASSERT_GE(rect.u1, code.u) << i;
        ASSERT_LE(rect.v0, code.v) << i;
        ASSERT_GE(rect.v1, code.v) << i;
        // The tile's grid (up to 64 cells a side) holds it in the ray's cell.
        const DirectionGrid grid = make_direction_grid(list, c, int(rng() % 7), scene);
        ASSERT_EQ(grid.cell(code.u, code.v).size(), 1u) << i;
        ++tested;
    }
    EXPECT_GT(tested, 2000);
}

TEST(Box, ContainsPointsAndBoxes) {
    Box b;
    EXPECT_FALSE(b.contains(Float3{0, 0, 0})) << "an empty box holds no point";
    b.extend(Float3{0, 0, 0});
    b.extend(Float3{1, 2, 3});
    EXPECT_TRUE(b.contains(Float3{0, 0, 0}));
    EXPECT_TRUE(b.contains(Float3{1, 2, 3})) << "faces included";
    EXPECT_TRUE(b.contains(Float3{0.5f, 1, 2}));
    EXPECT_FALSE(b.contains(Float3{1.0000001f, 1, 1}));
    EXPECT_FALSE(b.contains(Float3{0.5f, -1e-30f, 1}));
    EXPECT_FALSE(b.contains(Float3{NAN, 1, 1}));
    Box inner;
    inner.extend(Float3{0, 1, 1});
    inner.extend(Float3{1, 2, 2});
    EXPECT_TRUE(b.contains(inner));
    EXPECT_TRUE(b.contains(b));
    inner.extend(Float3{1, 2, 3.5f});
    EXPECT_FALSE(b.contains(inner));
    EXPECT_FALSE(inner.contains(b));
}
