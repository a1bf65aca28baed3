// The kd-tree against the brute-force reference: both use the same scalar-exact triangle test, so
// closest hits must have bit-identical t; the triangle may differ only when two triangles tie at t.
#include <gtest/gtest.h>

#include <bit>

#include "beamtrace/error.hpp"
#include "beamtrace/kdtree.hpp"
#include "kdtree/kd_node.hpp"
#include "test_scenes.hpp"

using namespace beamtrace;

namespace {

void expect_same_as_brute_force(const KdTree& tree, const std::vector<Ray>& rays) {
    int hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& r = rays[i];
        const Hit a = tree.intersect(r), b = intersect_brute_force(tree.scene(), r);
        ASSERT_EQ(a.hit(), b.hit()) << "ray " << i;
        if (a.hit()) {
            ++hits;
            ASSERT_EQ(a.t, b.t) << "ray " << i;  // different triangles only at a tie (+0 == -0)
            if (a.triangle == b.triangle) {
                ASSERT_EQ(std::bit_cast<std::uint32_t>(a.t), std::bit_cast<std::uint32_t>(b.t)) << "ray " << i;
                ASSERT_EQ(a.u, b.u);
                ASSERT_EQ(a.v, b.v);
            }
        }
        ASSERT_EQ(tree.occluded(r), occluded_brute_force(tree.scene(), r)) << "ray " << i;
    }
    EXPECT_GT(hits, 0);
}

}  // namespace

TEST(KdTree, NodesAreEightBytes) { EXPECT_EQ(sizeof(KdNode), 8u); }

// Every builder (test_scenes.hpp: the exact sweep, and binned upper levels at two settings) against
// the brute force.
class KdTreeBuilds : public ::testing::TestWithParam<test::BuildCase> {
protected:
    KdBuildRules rules() const { return GetParam().rules; }
};

TEST_P(KdTreeBuilds, RandomSoupEqualsBruteForce) {
    const Scene s = test::random_soup(3000, 1);
    const KdTree tree = KdTree::build(s, rules());
    expect_same_as_brute_force(tree, test::random_rays(s.bounds(), 20000, 2));
    expect_same_as_brute_force(tree, test::axis_rays(s, 5000, 3));
}

TEST_P(KdTreeBuilds, BoxesOnAGridEqualBruteForce) {
    // Faces on integer planes: planar triangles exactly on split planes, shared edges everywhere,
    // rays from inside the closed room.
    const Scene s = test::stacked_boxes(200, 4);
    const KdTree tree = KdTree::build(s, rules());
    EXPECT_GT(tree.stats().flat_cell_splits + tree.stats().flat_leaves, 0u);
    expect_same_as_brute_force(tree, test::random_rays(s.bounds(), 20000, 5));
    expect_same_as_brute_force(tree, test::axis_rays(s, 20000, 6));
}

TEST_P(KdTreeBuilds, SinglePlaneEqualsBruteForce) {
    const Scene s = test::single_plane(40);
    const KdTree tree = KdTree::build(s, rules());
    expect_same_as_brute_force(tree, test::random_rays(s.bounds(), 10000, 7));
    expect_same_as_brute_force(tree, test::axis_rays(s, 10000, 8));
}

TEST_P(KdTreeBuilds, EveryRuleSwitchedOffStillExact) {
    const Scene s = test::stacked_boxes(100, 9);
    KdBuildRules r = rules();
    r.empty_cell_rule = r.flat_cell_rule = r.tiny_cell_rule = false;
    expect_same_as_brute_force(KdTree::build(s, r), test::random_rays(s.bounds(), 10000, 10));
    r = rules();
    r.leaf_triangles = 8;
    r.max_depth = 3;
    expect_same_as_brute_force(KdTree::build(s, r), test::random_rays(s.bounds(), 10000, 11));
}

TEST(KdTree, RayIntervalIsRespected) {
    test::Soup soup;
    soup.add_quad({0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1});
    soup.add_quad({0, 0, 2}, {1, 0, 2}, {1, 1, 2}, {0, 1, 2});
    const KdTree tree = KdTree::build(soup.scene());
    const Float3 o{0.3f, 0.6f, 0.0f}, d{0, 0, 1};
    EXPECT_FLOAT_EQ(tree.intersect(Ray{o, 0.0f, d, kInfinity}).t, 1.0f);
    EXPECT_FLOAT_EQ(tree.intersect(Ray{o, 1.5f, d, kInfinity}).t, 2.0f);
    EXPECT_FALSE(tree.intersect(Ray{o, 1.1f, d, 1.9f}).hit());
    EXPECT_TRUE(tree.intersect(Ray{o, 1.0f, d, 1.0f}).hit());   // tfar == tnear on the surface
    EXPECT_FALSE(tree.intersect(Ray{o, 2.5f, d, 1.0f}).hit());  // tnear > tfar: empty interval
    EXPECT_FALSE(tree.occluded(Ray{o, 0.0f, d, 0.5f}));
    EXPECT_TRUE(tree.occluded(Ray{o, 0.0f, d, 1.5f}));
    EXPECT_FALSE(tree.intersect(Ray{o, 0.0f, Float3{0, 0, -1}, kInfinity}).hit());
}

// A negative tnear reaches behind the origin: planes crossed there must be followed too (the
// traversal once sent such rays only to the origin's side and lost every hit behind it).
TEST_P(KdTreeBuilds, NegativeTnearFindsHitsBehindTheOrigin) {
    const Scene s = test::random_soup(3000, 21);
    const KdTree tree = KdTree::build(s, rules());
    std::vector<Ray> rays = test::random_rays(s.bounds(), 5000, 22);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        rays[i].tnear = i % 2 ? -1e3f : -0.5f;
        if (i % 3 == 0) rays[i].tfar = 0.25f;  // the segment lies mostly behind the origin
    }
    expect_same_as_brute_force(tree, rays);
}

TEST_P(KdTreeBuilds, StatisticsAreConsistent) {
    const Scene s = test::random_soup(5000, 12);
    const KdTree tree = KdTree::build(s, rules());
    const KdBuildStats& st = tree.stats();
    EXPECT_EQ(st.triangles, 5000u);
    EXPECT_EQ(st.nodes, st.inner_nodes + st.leaves);
    EXPECT_EQ(st.leaves, st.inner_nodes + 1);
    EXPECT_GE(st.triangle_references, 5000u);
    // 8-byte nodes, 4-byte references and the 36 bytes of the corners stored beside each reference.
    EXPECT_EQ(st.bytes, st.nodes * 8 + st.triangle_references * (4 + 36));
    EXPECT_GT(st.depth, 5);
    EXPECT_GT(st.mean_triangles_per_leaf, 0.5);
    EXPECT_GT(st.empty_leaves, 0u);
    EXPECT_GE(st.build_seconds, 0.0);
    EXPECT_GT(st.sah_cost, 0.0);
    if (rules().binned_above > 0)
        EXPECT_GT(st.binned_splits, 0u);
    else
        EXPECT_EQ(st.binned_splits, 0u);
}

INSTANTIATE_TEST_SUITE_P(Builders, KdTreeBuilds, ::testing::ValuesIn(test::build_cases()),
                         [](const ::testing::TestParamInfo<test::BuildCase>& info) { return info.param.name; });

TEST(KdTree, DegenerateTrianglesAreCountedAndNeverHit) {
    test::Soup soup;
    soup.add({0, 0, 1}, {1, 0, 1}, {2, 0, 1});  // collinear
    soup.add({0, 0, 1}, {0, 0, 1}, {0, 1, 1});  // repeated corner
    soup.add({0, 0, 2}, {1, 0, 2}, {0, 1, 2});  // a real one behind
    const KdTree tree = KdTree::build(soup.scene());
    EXPECT_EQ(tree.stats().degenerate_triangles, 2u);
    const Hit h = tree.intersect(Ray{{0.0f, 0.0f, 0.0f}, 0.0f, {0, 0, 1}, kInfinity});
    ASSERT_TRUE(h.hit());
    EXPECT_EQ(h.triangle, 2u);
}

TEST(KdTree, AllDegenerateSceneHasNoHits) {
    test::Soup soup;
    for (int i = 0; i < 10; ++i) soup.add({0, 0, 0}, {0, 0, 0}, {0, 0, 0});
    const KdTree tree = KdTree::build(soup.scene());
    EXPECT_FALSE(tree.intersect(Ray{{0, 0, -1}, 0.0f, {0, 0, 1}, kInfinity}).hit());
    EXPECT_FALSE(tree.occluded(Ray{{0, 0, -1}, 0.0f, {0, 0, 1}, kInfinity}));
}

TEST(KdTree, CountersCountTheSameTraversal) {
    const Scene s = test::random_soup(2000, 13);
    const KdTree tree = KdTree::build(s);
    QueryCounters c;
    for (const Ray& r : test::random_rays(s.bounds(), 1000, 14)) {
        Hit counted;
        tree.intersect(std::span<const Ray>(&r, 1), std::span<Hit>(&counted, 1), QueryOptions{1, &c});
        const Hit plain = tree.intersect(r);
        ASSERT_EQ(plain.triangle, counted.triangle);
        ASSERT_EQ(plain.t, counted.t);
    }
    EXPECT_EQ(c.rays, 1000u);
    EXPECT_GT(c.inner_steps, c.leaves);
    EXPECT_GT(c.triangle_tests, 0u);
}

TEST(KdTree, ProgressIsReportedAndEndsAtOne) {
    const Scene s = test::random_soup(20000, 15);
    double last = -1.0;
    bool monotonic = true;
    KdTree::build(s, {}, [&](double f) {
        monotonic = monotonic && f >= last;
        last = f;
    });
    EXPECT_TRUE(monotonic);
    EXPECT_DOUBLE_EQ(last, 1.0);
}
