// The wide BVH: its build holds every non-degenerate triangle once, in leaves of bounded size under
// boxes that contain them; its traversal answers as the kd-tree does (the same t; at equal t the hit
// may be another triangle's, one the ray meets there), every instruction set's kernels bit for bit
// as the scalar reference, including rays along zero direction components with origins in planes
// of the scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/error.hpp"
#include "beamtrace/kdtree.hpp"
#include "bvh/wide_bvh.hpp"
#include "common/triangle_reference.hpp"
#include "common/watertight_ray.hpp"
#include "../kdtree/test_scenes.hpp"

using namespace beamtrace;

namespace {

bool hits_at(const Scene& scene, const Ray& ray, std::uint32_t triangle, float t) {
    TriangleHit h;
    return intersect_triangle(make_watertight_ray(ray), scene.triangle(triangle), h) && h.t == t;
}

// Rays of every kind the tests use: random rays in and around the box, rays along axes through the
// scene's own coordinates, short segments and rays starting beyond their end.
std::vector<Ray> test_rays(const Scene& scene, unsigned seed) {
    std::vector<Ray> rays = test::random_rays(scene.bounds(), 3000, seed);
    const std::vector<Ray> axis = test::axis_rays(scene, 1500, seed + 1);
    rays.insert(rays.end(), axis.begin(), axis.end());
    std::mt19937 random(seed + 2);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 500; ++i) {
        Ray r = rays[std::size_t(i)];
        r.tfar = u(random) * 0.3f * scene.bounds().diagonal();
        r.tnear = i % 7 == 0 ? r.tfar * 0.5f : 0.0f;
        rays.push_back(r);
    }
    return rays;
}

// Every ISA's kernels (and the reference) against the kd-tree on the scene.
void expect_answers_as_kd_tree(const Scene& scene, const bvh::WideBvhSettings& settings, unsigned seed) {
    const KdTree tree = KdTree::build(scene);
    const auto bvh = bvh::WideBvh::build(scene, settings);
    const std::vector<Ray> rays = test_rays(scene, seed);
    const bvh::WideBvhKernels& reference = bvh::wide_bvh_kernels(Isa::scalar);
    int hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& r = rays[i];
        const Hit want = tree.intersect(r);
        const Hit got = reference.intersect(*bvh, r);
        ASSERT_EQ(got.hit(), want.hit()) << "ray " << i;
        EXPECT_EQ(reference.occluded(*bvh, r).hit(), tree.occluded(r)) << "ray " << i;
        if (want.hit()) {
            ++hits;
            ASSERT_EQ(got.t, want.t) << "ray " << i;
            if (got.triangle != want.triangle)
                EXPECT_TRUE(hits_at(scene, r, got.triangle, got.t)) << "ray " << i;
            else
                EXPECT_EQ(got.u, want.u);
        }
        for (Isa isa : {Isa::sse42, Isa::avx2, Isa::avx512}) {
            if (!isa_available(isa)) continue;
            const bvh::WideBvhKernels& k = bvh::wide_bvh_kernels(isa);
            const Hit h = k.intersect(*bvh, r);
            ASSERT_EQ(h.triangle, got.triangle) << isa_name(isa) << " ray " << i;
            ASSERT_EQ(h.t, got.t) << isa_name(isa) << " ray " << i;
            ASSERT_EQ(h.u, got.u) << isa_name(isa) << " ray " << i;
            ASSERT_EQ(h.v, got.v) << isa_name(isa) << " ray " << i;
            const Hit o = k.occluded(*bvh, r), o_ref = reference.occluded(*bvh, r);
            ASSERT_EQ(o.triangle, o_ref.triangle) << isa_name(isa) << " ray " << i;
            QueryCounters a, b;
            EXPECT_EQ(k.intersect_counted(*bvh, r, &a).t, got.t);
            reference.intersect_counted(*bvh, r, &b);
            EXPECT_EQ(a.inner_steps, b.inner_steps);
            EXPECT_EQ(a.triangle_tests, b.triangle_tests);
        }
    }
    EXPECT_GT(hits, 200);
}

// Every triangle of the subtree at `ref` lies in `box`; the triangles seen are marked.
void check_subtree(const bvh::WideBvh& b, const Scene& scene, std::uint32_t ref, const Box& box, int max_leaf,
                   std::vector<int>& seen) {
    if (ref == bvh::kEmpty) return;
    if (bvh::is_leaf(ref)) {
        const std::uint32_t n = bvh::leaf_count(ref);
        ASSERT_LE(n, std::uint32_t(max_leaf));
        for (std::uint32_t k = bvh::leaf_first(ref); k < bvh::leaf_first(ref) + n; ++k) {
            const std::uint32_t id = b.triangle_ids[k];
            ++seen[id];
            const Triangle& t = scene.triangle(id);
            EXPECT_TRUE(box.contains(t.v0) && box.contains(t.v1) && box.contains(t.v2));
            const float* v = &t.v0.x;
            const std::size_t first = bvh::leaf_first(ref);
            for (std::size_t c = 0; c < 9; ++c) EXPECT_EQ(b.rows[9 * first + c * n + (k - first)], v[c]);
        }
        return;
    }
    const bvh::WideNode& node = b.nodes[bvh::node_index(ref)];
    int children = 0;
    for (int c = 0; c < bvh::kWidth; ++c) {
        if (node.child[c] == bvh::kEmpty) continue;
        ++children;
        Box child;
        child.lower = Float3{node.lower[0][c], node.lower[1][c], node.lower[2][c]};
        child.upper = Float3{node.upper[0][c], node.upper[1][c], node.upper[2][c]};
        EXPECT_TRUE(box.contains(child));
        check_subtree(b, scene, node.child[c], child, max_leaf, seen);
    }
    EXPECT_GE(children, 2);
    EXPECT_EQ(children, bvh::node_children(ref));  // the reference says how many, and they come first
    for (int c = children; c < bvh::kWidth; ++c) EXPECT_EQ(node.child[c], bvh::kEmpty);
}

}  // namespace

TEST(WideBvh, HoldsEveryTriangleOnceUnderBoxesThatContainIt) {
    for (int max_leaf : {1, 4, 8, 16}) {
        const Scene scene = test::random_soup(3000, 5);
        bvh::WideBvhSettings s;
        s.max_leaf_triangles = max_leaf;
        const auto b = bvh::WideBvh::build(scene, s);
        std::vector<int> seen(scene.triangle_count(), 0);
        Box all;
        all.extend(scene.bounds());
        check_subtree(*b, scene, b->root, all, max_leaf, seen);
        for (std::uint32_t t = 0; t < scene.triangle_count(); ++t)
            ASSERT_EQ(seen[t], scene.is_degenerate(t) ? 0 : 1) << "triangle " << t;
        EXPECT_EQ(b->stats.triangles, scene.triangle_count() - scene.degenerate_count());
        EXPECT_GT(b->stats.memory_bytes, b->stats.inner_nodes * sizeof(bvh::WideNode));
        EXPECT_LE(b->stats.depth, bvh::WideBvh::kMaxDepth);
    }
}

TEST(WideBvh, CoincidentCentresStillSplit) {
    // 200 copies of one triangle: no centroid split exists; the build splits by count.
    test::Soup soup;
    for (int i = 0; i < 200; ++i) soup.add({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    const Scene scene = soup.scene();
    const auto b = bvh::WideBvh::build(scene);
    std::vector<int> seen(scene.triangle_count(), 0);
    check_subtree(*b, scene, b->root, scene.bounds(), bvh::WideBvhSettings{}.max_leaf_triangles, seen);
    for (int s : seen) EXPECT_EQ(s, 1);
    const Hit h = bvh::wide_bvh_kernels().intersect(*b, Ray{{0.25f, 0.25f, 1}, 0, {0, 0, -1}, kInfinity});
    EXPECT_TRUE(h.hit());
    EXPECT_EQ(h.t, 1.0f);
}

TEST(WideBvh, SmallSceneIsOneLeaf) {
    test::Soup soup;
    soup.add({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    soup.add({0, 0, 0}, {0, 0, 0}, {0, 1, 0});  // degenerate: left out
    const auto b = bvh::WideBvh::build(soup.scene());
    EXPECT_TRUE(bvh::is_leaf(b->root));
    EXPECT_EQ(bvh::leaf_count(b->root), 1u);
    EXPECT_EQ(b->stats.inner_nodes, 0u);
    const Hit h = bvh::wide_bvh_kernels().intersect(*b, Ray{{0.25f, 0.25f, 1}, 0, {0, 0, -1}, kInfinity});
    EXPECT_EQ(h.triangle, 0u);
}

TEST(WideBvh, OnlyDegenerateTrianglesMakeAnEmptyTreeThatNothingHits) {
    test::Soup soup;
    soup.add({0, 0, 0}, {0, 0, 0}, {0, 1, 0});
    soup.add({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
    const Scene scene = soup.scene();
    const auto b = bvh::WideBvh::build(scene);
    EXPECT_EQ(b->root, bvh::kEmpty);
    EXPECT_EQ(b->stats.triangles, 0u);
    const Ray ray{{0.1f, 0.1f, 1}, 0, {0, 0, -1}, kInfinity};
    for (Isa isa : {Isa::scalar, Isa::sse42, Isa::avx2, Isa::avx512}) {
        if (isa != Isa::scalar && !isa_available(isa)) continue;
        EXPECT_FALSE(bvh::wide_bvh_kernels(isa).intersect(*b, ray).hit());
        EXPECT_FALSE(bvh::wide_bvh_kernels(isa).occluded(*b, ray).hit());
    }
}

TEST(WideBvh, RefusesBadSettings) {
    const Scene scene = test::single_plane(4);
    for (int leaf : {0, 17}) {
        bvh::WideBvhSettings s;
        s.max_leaf_triangles = leaf;
        try {
            bvh::WideBvh::build(scene, s);
            ADD_FAILURE() << "accepted max_leaf_triangles " << leaf;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("max_leaf_triangles"), std::string::npos);
        }
    }
    bvh::WideBvhSettings s;
    s.bins = 2;
    EXPECT_THROW(bvh::WideBvh::build(scene, s), Error);
}

TEST(WideBvh, AnswersAsTheKdTreeOnRandomSoup) { expect_answers_as_kd_tree(test::random_soup(4000, 21), {}, 40); }

TEST(WideBvh, AnswersAsTheKdTreeOnBoxesAlongAxes) {
    // Axis-aligned faces on box planes, rays along them: the NaN slab distances.
    expect_answers_as_kd_tree(test::stacked_boxes(80, 22), {}, 41);
}

TEST(WideBvh, AnswersAsTheKdTreeOnOnePlaneAndEveryLeafSize) {
    for (int leaf : {1, 3, 16}) {
        bvh::WideBvhSettings s;
        s.max_leaf_triangles = leaf;
        expect_answers_as_kd_tree(test::single_plane(20), s, 42 + unsigned(leaf));
    }
}
