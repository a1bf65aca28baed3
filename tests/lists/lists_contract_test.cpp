// The query contract of SortedLists (query.hpp): rays that describe no segment report nothing, bad
// rules and bad spans are errors with a message, the counting variant answers the same as the plain
// one, and the structure is what the rules ask for (the paper's hierarchy: tetra:L with a 2x2x2 grid
// is four children per level, L levels of them; the flat lists are one volume).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "beamtrace/error.hpp"
#include "beamtrace/sorted_lists.hpp"
#include "scenes/scene_source.hpp"
#include "test_scenes.hpp"

using namespace beamtrace;

namespace {

void expect_error(const SortedListRules& rules, const std::string& needle) {
    const Scene scene = test::random_soup(10, 1);
    try {
        SortedLists::build(scene, rules);
        FAIL() << "accepted bad rules (" << needle << ")";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(ListsContract, BadRulesAreErrors) {
    SortedListRules r;
    r.grid[1] = 0;
    expect_error(r, "grid[1]");
    r = {};
    r.grid[2] = 17;
    expect_error(r, "grid[2]");
    r = {};
    r.grid[0] = r.grid[1] = r.grid[2] = 1;
    expect_error(r, "at least 2 cells");
    r.flat = true;  // a flat structure needs no grid
    EXPECT_NO_THROW(SortedLists::build(test::random_soup(10, 1), r));
    r = {};
    r.leaf_objects = 0;
    expect_error(r, "leaf_objects");
    r = {};
    r.special_cell_fraction = 0.0f;
    expect_error(r, "special_cell_fraction");
    r.special_cell_fraction = std::numeric_limits<float>::quiet_NaN();
    expect_error(r, "special_cell_fraction");
}

TEST(ListsContract, BadSpansAndThreadsAreErrors) {
    const SortedLists lists = SortedLists::build(test::random_soup(50, 2));
    std::vector<Ray> rays(3);
    std::vector<Hit> hits(2);
    std::vector<std::uint8_t> occluded(4);
    EXPECT_THROW(lists.intersect(rays, hits), Error);
    EXPECT_THROW(lists.occluded(rays, occluded), Error);
    hits.resize(3);
    EXPECT_THROW(lists.intersect(rays, hits, {0, nullptr}), Error);
    std::vector<Packet16> packets(2);
    std::vector<PacketHits16> packet_hits(1);
    std::vector<std::uint32_t> packet_occluded(3);
    EXPECT_THROW(lists.intersect(packets, packet_hits), Error);
    EXPECT_THROW(lists.occluded(packets, packet_occluded), Error);
}

TEST(ListsContract, RaysThatDescribeNoSegmentReportNothing) {
    const Scene scene = test::random_soup(200, 3, 0.3f);
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const Float3 c{0.5f, 0.5f, 0.5f};
    const std::vector<Ray> bad = {Ray{c, 0.0f, Float3{0, 0, 0}, inf},
                                  Ray{c, 0.0f, Float3{nan, 1, 0}, inf},
                                  Ray{Float3{inf, 0, 0}, 0.0f, Float3{1, 0, 0}, inf},
                                  Ray{c, 2.0f, Float3{1, 0, 0}, 1.0f},
                                  Ray{c, nan, Float3{1, 0, 0}, inf},
                                  Ray{c, 0.0f, Float3{1, 0, 0}, nan},
                                  Ray{c, -inf, Float3{1, 0, 0}, inf}};
    for (bool flat : {false, true}) {
        SortedListRules r;
        r.flat = flat;
        const SortedLists lists = SortedLists::build(scene, r);
        for (const Ray& ray : bad) {
            EXPECT_FALSE(lists.intersect(ray).hit());
            EXPECT_FALSE(lists.occluded(ray));
        }
    }
}

TEST(ListsContract, CountingAnswersTheSameAndCounts) {
    const Scene scene = scenes::load_scene("tetra:3").scene;
    const std::vector<Ray> rays = test::random_rays(scene.bounds(), 3000, 4);
    for (bool flat : {false, true}) {
        SortedListRules r;
        r.flat = flat;
        const SortedLists lists = SortedLists::build(scene, r);
        std::vector<Hit> plain(rays.size()), counted(rays.size());
        lists.intersect(rays, plain);
        QueryCounters c;
        lists.intersect(rays, counted, {2, &c});
        for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(plain[i].triangle, counted[i].triangle) << i;
        EXPECT_EQ(c.rays, rays.size());
        EXPECT_GT(c.triangle_tests, 0u);
        EXPECT_GT(c.lists.events, c.lists.walked_events);
        EXPECT_GT(c.lists.volumes_opened, 0u);
        EXPECT_GT(c.lists.heap_ops, 0u);
        // Only triangles whose box the ray enters are tested: far fewer than brute force.
        EXPECT_LT(c.triangle_tests, rays.size() * scene.triangle_count() / 8);
    }
}

TEST(ListsContract, HierarchyHasThePapersShape) {
    // tetra:L has 4^(L+1) triangles; the 2x2x2 grid puts its four sub-tetrahedra in four cells, so
    // with 4 objects per leaf the hierarchy has L + 1 levels (the paper: "8 levels, 4 nodes for each
    // level" at 65,536 triangles, tetra:7).
    for (int level : {0, 1, 2, 3, 4, 5, 7}) {
        const Scene scene = scenes::load_scene("tetra:" + std::to_string(level)).scene;
        const SortedListStats s = SortedLists::build(scene).stats();
        EXPECT_EQ(s.triangles, scene.triangle_count());
        EXPECT_EQ(s.depth, level + 1) << "tetra:" << level;
        EXPECT_GT(s.mean_children, 3.5) << "tetra:" << level;
        EXPECT_LE(s.mean_children, 4.0) << "tetra:" << level;
        EXPECT_GT(s.memory_bytes, 0u);
        SortedListRules r;
        r.flat = true;
        const SortedListStats f = SortedLists::build(scene, r).stats();
        EXPECT_EQ(f.volumes, 1u);
        EXPECT_EQ(f.depth, 1);
        EXPECT_EQ(f.events, 6 * scene.triangle_count());
    }
}

TEST(ListsContract, DegenerateTrianglesAreLeftOut) {
    test::Soup s;
    s.add(Float3{0, 0, 0}, Float3{1, 0, 0}, Float3{0, 1, 0});
    s.add(Float3{0, 0, 1}, Float3{0, 0, 1}, Float3{1, 1, 1});  // repeated corner
    s.add(Float3{0, 0, 2}, Float3{1, 1, 2}, Float3{2, 2, 2});  // collinear
    const SortedLists lists = SortedLists::build(s.scene());
    EXPECT_EQ(lists.stats().degenerate_triangles, 2u);
    EXPECT_EQ(lists.stats().events, 6u);
    const Hit h = lists.intersect(Ray{Float3{0.25f, 0.25f, -1}, 0.0f, Float3{0, 0, 1}, kInfinity});
    EXPECT_EQ(h.triangle, 0u);
    EXPECT_EQ(h.t, 1.0f);
}
