// Whole streams: the stream tracer answers every ray as the kd-tree does, whatever the order the
// rays come in, on one thread or two, sorted or not; it rejects bad input with a message.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "beamtrace/error.hpp"
#include "beamtrace/stream.hpp"
#include "common/triangle_reference.hpp"
#include "common/watertight_ray.hpp"
#include "../kdtree/test_scenes.hpp"

using namespace beamtrace;

namespace {

// A stream as an integrator hands it over: primary rays from a camera, ambient-occlusion rays (16
// from each of a number of points), shadow rays towards two lights, scattered rays, and a few rays
// that describe no segment; shuffled.
std::vector<Ray> mixed_stream(const Scene& scene, unsigned seed) {
    std::mt19937 random(seed);
    const Box b = scene.bounds();
    const Float3 e = b.extent();
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    auto inside = [&] {
        return Float3{b.lower.x + e.x * u(random), b.lower.y + e.y * u(random), b.lower.z + e.z * u(random)};
    };
    auto direction = [&] { return Float3{u(random) - 0.5f, u(random) - 0.5f, u(random) - 0.5f}; };
    std::vector<Ray> rays;
    const Float3 camera = b.lower - e * 0.3f;
    for (int i = 0; i < 1500; ++i) rays.push_back(Ray{camera, 0.0f, inside() - camera, kInfinity});
    const float reach = 0.2f * std::sqrt(dot(e, e));
    for (int p = 0; p < 150; ++p) {
        const Float3 o = inside();
        for (int i = 0; i < 16; ++i) {
            const Float3 d = direction();
            rays.push_back(Ray{o, 0.0f, d * (1.0f / std::sqrt(dot(d, d))), reach});
        }
    }
    const Float3 lights[2] = {inside(), inside()};
    for (int i = 0; i < 1600; ++i) {
        const Float3 o = inside();
        rays.push_back(Ray{o, 0.0f, lights[i % 2] - o, 1.0f - 1e-4f});
    }
    for (int i = 0; i < 1000; ++i) rays.push_back(Ray{inside(), 0.0f, direction(), kInfinity});
    rays.push_back(Ray{camera, 0.0f, {0, 0, 0}, 1.0f});
    rays.push_back(Ray{{NAN, 0, 0}, 0.0f, {1, 0, 0}, 1.0f});
    rays.push_back(Ray{camera, 3.0f, {1, 0, 0}, 1.0f});
    std::shuffle(rays.begin(), rays.end(), random);
    return rays;
}

// Whether the ray hits the triangle exactly at t (the watertight reference).
bool hits_at(const Scene& scene, const Ray& ray, std::uint32_t triangle, float t) {
    TriangleHit h;
    return intersect_triangle(make_watertight_ray(ray), scene.triangle(triangle), h) && h.t == t;
}

// got[i] is want[i], or a hit on another triangle at exactly the same distance.
void expect_same_hits(const Scene& scene, const std::vector<Ray>& rays, const std::vector<Hit>& got,
                      const std::vector<Hit>& want, const std::string& what) {
    int hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(got[i].hit(), want[i].hit()) << what << " ray " << i;
        if (!want[i].hit()) continue;
        ++hits;
        ASSERT_EQ(got[i].t, want[i].t) << what << " ray " << i;
        if (got[i].triangle != want[i].triangle) {
            EXPECT_TRUE(hits_at(scene, rays[i], got[i].triangle, got[i].t)) << what << " ray " << i;
        } else {
            EXPECT_EQ(got[i].u, want[i].u);
            EXPECT_EQ(got[i].v, want[i].v);
        }
    }
    EXPECT_GT(hits, 100) << what;
}

struct Answers {
    std::vector<Hit> hits;
    std::vector<std::uint8_t> occluded;
};

Answers answers(const StreamTracer& tracer, const std::vector<Ray>& rays, const QueryOptions& options = {}) {
    Answers a{std::vector<Hit>(rays.size()), std::vector<std::uint8_t>(rays.size())};
    tracer.intersect(rays, a.hits, options);
    tracer.occluded(rays, a.occluded, options);
    return a;
}

// The tracer's closest hits and occlusion answers to `rays` are the kd-tree's (one thread); returns
// the tracer's counters of both calls.
QueryCounters expect_the_kd_trees_answers(const Scene& scene, const KdTree& tree, const StreamTracer& tracer,
                                          const std::vector<Ray>& rays, const std::string& what) {
    std::vector<Hit> want(rays.size());
    std::vector<std::uint8_t> want_occluded(rays.size());
    tree.intersect(rays, want);
    tree.occluded(rays, want_occluded);
    QueryCounters counters;
    const Answers got = answers(tracer, rays, QueryOptions{1, &counters});
    expect_same_hits(scene, rays, got.hits, want, what);
    EXPECT_EQ(got.occluded, want_occluded) << what;
    return counters;
}

class StreamTracerScenes : public ::testing::TestWithParam<int> {
protected:
    Scene scene() const {
        switch (GetParam()) {
            case 0:
                return test::random_soup(4000, 21);
            case 1:
                return test::stacked_boxes(80, 22);
            default:
                return test::single_plane(20);
        }
    }
};

}  // namespace

TEST_P(StreamTracerScenes, AnswersAsTheKdTree) {
    const Scene s = scene();
    const KdTree tree = KdTree::build(s);
    const std::vector<Ray> rays = mixed_stream(s, 30 + unsigned(GetParam()));
    std::vector<Hit> want(rays.size());
    std::vector<std::uint8_t> want_occluded(rays.size());
    tree.intersect(rays, want);
    tree.occluded(rays, want_occluded);
    // The defaults: rays in no group through the wide BVH.
    const StreamTracer with_bvh(tree);
    EXPECT_GT(with_bvh.wide_bvh_bytes(), 0u);
    const QueryCounters by_bvh = expect_the_kd_trees_answers(s, tree, with_bvh, rays, "sorted, wide BVH");
    EXPECT_GT(by_bvh.stream.origin_groups, 0u);
    EXPECT_GT(by_bvh.stream.pencil_packets, 0u);
    EXPECT_EQ(by_bvh.stream.loose_groups, 0u);
    EXPECT_GT(by_bvh.stream.single_rays, 0u);
    // Every ray traced alone went through the BVH: the stream's singles and the lanes of pencil
    // packets the BVH's packet walk could not bound (directions of several octants, a few a packet).
    // (single_rays also counts lanes the kd-tree's groups trace alone, hence the bounds.)
    EXPECT_GE(by_bvh.rays, by_bvh.stream.single_rays);
    EXPECT_LE(by_bvh.rays, by_bvh.stream.single_rays + by_bvh.single_rays);
    EXPECT_GT(by_bvh.packets, 0u);  // occlusion pencils walked the BVH as packets (bvh_pencils)
    // Pencils through the kd-tree's interval traversal instead: the same answers.
    StreamSettings kd_pencils;
    kd_pencils.bvh_pencils = false;
    const QueryCounters by_kd_pencils =
        expect_the_kd_trees_answers(s, tree, StreamTracer(tree, kd_pencils), rays, "sorted, pencils by the kd-tree");
    EXPECT_EQ(by_kd_pencils.rays, by_kd_pencils.stream.single_rays);
    for (std::size_t i = 0; i < rays.size(); i += 97) {
        const Hit h = with_bvh.intersect(rays[i]);
        EXPECT_EQ(h.t, want[i].t) << "ray " << i;
        EXPECT_EQ(with_bvh.occluded(rays[i]), bool(want_occluded[i])) << "ray " << i;
    }
    StreamSettings unsorted_bvh;
    unsorted_bvh.sort = false;
    const Answers plain_bvh = answers(StreamTracer(tree, unsorted_bvh), rays, QueryOptions{2, nullptr});
    expect_same_hits(s, rays, plain_bvh.hits, want, "unsorted, wide BVH, two threads");
    EXPECT_EQ(plain_bvh.occluded, want_occluded);
    // The kd-tree alone.
    StreamSettings kd_only;
    kd_only.wide_bvh = false;
    const StreamTracer tracer(tree, kd_only);
    EXPECT_EQ(tracer.wide_bvh_bytes(), 0u);
    QueryCounters counters;
    const Answers got = answers(tracer, rays, QueryOptions{1, &counters});
    expect_same_hits(s, rays, got.hits, want, "sorted");
    EXPECT_EQ(got.occluded, want_occluded);
    // The stream was grouped: one-origin groups, pencils through the camera and the lights, the
    // scattered rays as loose groups of sorted neighbours.
    EXPECT_GT(counters.stream.origin_groups, 0u);
    EXPECT_GT(counters.stream.pencil_packets, 0u);
    EXPECT_GT(counters.stream.loose_groups, 0u);
    EXPECT_EQ(counters.stream.rays, 2 * rays.size());
    EXPECT_LE(counters.stream.origin_group_rays + counters.stream.pencil_rays + counters.stream.single_rays +
                  counters.stream.loose_group_rays,
              2 * rays.size());
    // The same answers on two threads and unsorted.
    const Answers two = answers(tracer, rays, QueryOptions{2, nullptr});
    expect_same_hits(s, rays, two.hits, want, "two threads");
    EXPECT_EQ(two.occluded, want_occluded);
    StreamSettings unsorted = kd_only;
    unsorted.sort = false;
    const Answers plain = answers(StreamTracer(tree, unsorted), rays);
    expect_same_hits(s, rays, plain.hits, want, "unsorted");
    EXPECT_EQ(plain.occluded, want_occluded);
    // Loose rays one by one: the same answers.
    StreamSettings one_by_one = kd_only;
    one_by_one.group_loose_rays = false;
    QueryCounters alone;
    const Answers singles = answers(StreamTracer(tree, one_by_one), rays, QueryOptions{1, &alone});
    expect_same_hits(s, rays, singles.hits, want, "loose rays one by one");
    EXPECT_EQ(singles.occluded, want_occluded);
    EXPECT_EQ(alone.stream.loose_groups, 0u);
    EXPECT_GE(alone.stream.single_rays, counters.stream.loose_group_rays);
}

TEST_P(StreamTracerScenes, DiffuseBouncesGoInLooseGroupsOrTheWideBvhAndAnswerAsTheKdTree) {
    // One closest-hit ray from each of 20,000 points (a diffuse bounce per hit): no two share an
    // origin or an end point, so every ray is loose; in windows of sorted neighbours, put in order
    // of direction, they go 16 at a time through the masked group traversal.
    const Scene s = scene();
    const KdTree tree = KdTree::build(s);
    const Box b = s.bounds();
    const Float3 e = b.extent();
    std::mt19937 random(70 + unsigned(GetParam()));
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Ray> rays;
    for (int i = 0; i < 20000; ++i) {
        const Float3 o{b.lower.x + e.x * u(random), b.lower.y + e.y * u(random), b.lower.z + e.z * u(random)};
        rays.push_back(Ray{o, 0.0f, Float3{u(random) - 0.5f, u(random) - 0.5f, u(random) - 0.5f}, kInfinity});
    }
    StreamSettings kd_only;
    kd_only.wide_bvh = false;
    const QueryCounters counters =
        expect_the_kd_trees_answers(s, tree, StreamTracer(tree, kd_only), rays, "loose groups");
    EXPECT_EQ(counters.stream.loose_group_rays, 2 * rays.size());
    EXPECT_EQ(counters.stream.single_rays, 0u);
    EXPECT_GE(double(counters.stream.loose_group_rays) / double(counters.stream.loose_groups), 15.0);
    // With the wide BVH (the default) every one of them goes through it alone, in the bucket pass's
    // order (no shared point).
    const QueryCounters by_bvh = expect_the_kd_trees_answers(s, tree, StreamTracer(tree), rays, "wide BVH");
    EXPECT_EQ(by_bvh.stream.single_rays, 2 * rays.size());
    EXPECT_EQ(by_bvh.rays, 2 * rays.size());
    EXPECT_EQ(by_bvh.stream.loose_groups, 0u);
    EXPECT_EQ(by_bvh.stream.bucket_ordered_rays, 2 * rays.size());
    // The whole sort instead: the same answers.
    StreamSettings sorted;
    sorted.bucket_order = false;
    const QueryCounters whole = expect_the_kd_trees_answers(s, tree, StreamTracer(tree, sorted), rays, "whole sort");
    EXPECT_EQ(whole.stream.bucket_ordered_rays, 0u);
    EXPECT_EQ(whole.stream.single_rays, 2 * rays.size());
    // Ambient-occlusion-like rays (8 from each of 2,500 of the points, shuffled): in buckets too, one
    // by one; sorted whole, in groups of one origin.
    std::vector<Ray> ao;
    for (int i = 0; i < 2500; ++i)
        for (int k = 0; k < 8; ++k)
            ao.push_back(
                Ray{rays[std::size_t(i)].org, 0.0f, Float3{u(random) - 0.5f, u(random) - 0.5f, 0.5f}, 0.3f * e.x});
    std::shuffle(ao.begin(), ao.end(), random);
    const QueryCounters ao_buckets = expect_the_kd_trees_answers(s, tree, StreamTracer(tree), ao, "ao in buckets");
    EXPECT_EQ(ao_buckets.stream.bucket_ordered_rays, 2 * ao.size());
    EXPECT_EQ(ao_buckets.stream.origin_groups, 0u);
    const QueryCounters ao_sorted =
        expect_the_kd_trees_answers(s, tree, StreamTracer(tree, sorted), ao, "ao sorted whole");
    EXPECT_EQ(ao_sorted.stream.bucket_ordered_rays, 0u);
    EXPECT_GT(ao_sorted.stream.origin_group_rays, ao.size());
    // A stream with a shared point (a camera) is sorted whole: its pencils are grouped.
    std::vector<Ray> with_camera = rays;
    const Float3 eye{b.lower.x - e.x, b.lower.y + 0.5f * e.y, b.lower.z + 0.5f * e.z};
    for (int i = 0; i < 5000; ++i) with_camera.push_back(Ray{eye, 0.0f, rays[std::size_t(i)].org - eye, kInfinity});
    std::shuffle(with_camera.begin(), with_camera.end(), random);
    const QueryCounters mixed = expect_the_kd_trees_answers(s, tree, StreamTracer(tree), with_camera, "camera");
    EXPECT_EQ(mixed.stream.bucket_ordered_rays, 0u);
    EXPECT_GT(mixed.stream.pencil_packets, 0u);
}

TEST_P(StreamTracerScenes, AnswersDoNotDependOnTheInputOrder) {
    const Scene s = scene();
    const KdTree tree = KdTree::build(s);
    const StreamTracer tracer(tree);
    const std::vector<Ray> rays = mixed_stream(s, 40 + unsigned(GetParam()));
    const Answers first = answers(tracer, rays);
    for (unsigned seed : {1u, 2u}) {
        std::vector<std::size_t> perm(rays.size());
        std::iota(perm.begin(), perm.end(), std::size_t{0});
        std::mt19937 random(seed);
        std::shuffle(perm.begin(), perm.end(), random);
        if (seed == 2) std::reverse(perm.begin(), perm.end());
        std::vector<Ray> reordered(rays.size());
        for (std::size_t i = 0; i < rays.size(); ++i) reordered[i] = rays[perm[i]];
        const Answers again = answers(tracer, reordered);
        std::vector<Hit> back(rays.size());
        std::vector<std::uint8_t> back_occluded(rays.size());
        for (std::size_t i = 0; i < rays.size(); ++i) {
            back[perm[i]] = again.hits[i];
            back_occluded[perm[i]] = again.occluded[i];
        }
        expect_same_hits(s, rays, back, first.hits, "reordered");
        EXPECT_EQ(back_occluded, first.occluded);
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, StreamTracerScenes, ::testing::Values(0, 1, 2));

TEST(StreamTracer, RejectsBadInputWithAMessage) {
    const KdTree tree = KdTree::build(test::random_soup(100, 50));
    const StreamTracer tracer(tree);
    std::vector<Ray> rays(10, Ray{{0, 0, 0}, 0.0f, {1, 0, 0}, 1.0f});
    std::vector<Hit> hits(9);
    EXPECT_THROW(tracer.intersect(rays, hits), Error);
    std::vector<std::uint8_t> occluded(10);
    EXPECT_THROW(tracer.occluded(rays, occluded, QueryOptions{0, nullptr}), Error);
    StreamSettings bad;
    bad.min_group_rays = 1;
    EXPECT_THROW(StreamTracer(tree, bad), Error);
    bad = StreamSettings{};
    bad.shared_point_fraction = 0.0f;
    EXPECT_THROW(StreamTracer(tree, bad), Error);
    std::vector<std::uint32_t> order(3);
    EXPECT_THROW(stream_order(rays, tree.scene().bounds(), true, order), Error);
}

TEST(StreamTracer, StreamOrderIsAPermutation) {
    const Scene s = test::stacked_boxes(20, 51);
    const std::vector<Ray> rays = mixed_stream(s, 52);
    std::vector<std::uint32_t> order(rays.size());
    stream_order(rays, s.bounds(), false, order);
    std::vector<std::uint32_t> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);
}

TEST(StreamTracer, EmptyStreamsAndSingleRays) {
    const Scene s = test::random_soup(300, 53);
    const KdTree tree = KdTree::build(s);
    const StreamTracer tracer(tree);
    std::vector<Ray> none;
    std::vector<Hit> no_hits;
    tracer.intersect(none, no_hits);
    const std::vector<Ray> rays = test::random_rays(s.bounds(), 50, 54);
    for (const Ray& r : rays) {
        EXPECT_EQ(tracer.intersect(r).triangle, tree.intersect(r).triangle);
        EXPECT_EQ(tracer.occluded(r), tree.occluded(r));
    }
}

TEST(StreamTracer, StreamsBeyondTheCachesAnswerFromTheBucketRecords) {
    // A million and more rays with no shared point: bucketed, then traced where the bucket pass put
    // them (no copy into sorted arrays). Answers as the kd-tree's; stream_order a permutation.
    const Scene s = test::random_soup(2000, 62);
    const KdTree tree = KdTree::build(s);
    const Box b = s.bounds();
    const Float3 e = b.extent();
    std::mt19937 random(63);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Ray> rays(std::size_t{1} << 20 | 7);
    for (Ray& r : rays) {
        const Float3 o{b.lower.x + e.x * u(random), b.lower.y + e.y * u(random), b.lower.z + e.z * u(random)};
        r = Ray{o, 0.0f, Float3{u(random) - 0.5f, u(random) - 0.5f, u(random) - 0.5f}, 0.25f * e.x};
    }
    const QueryCounters counters = expect_the_kd_trees_answers(s, tree, StreamTracer(tree), rays, "from the records");
    EXPECT_EQ(counters.stream.bucket_ordered_rays, 2 * rays.size());
    EXPECT_EQ(counters.stream.single_rays, 2 * rays.size());
    std::vector<std::uint32_t> order(rays.size());
    stream_order(rays, b, true, order);
    std::vector<bool> seen(rays.size(), false);
    for (const std::uint32_t i : order) {
        ASSERT_LT(i, rays.size());
        ASSERT_FALSE(seen[i]);
        seen[i] = true;
    }
}

TEST(StreamTracer, ManyOriginsInOneCellAnswerAsTheKdTree) {
    // 400 origins inside one origin cell, 16 rays each, shuffled: the whole sort (no bucket order)
    // puts each origin's rays together (some origins share their hash bits and interleave: traced one
    // by one), the answers are the kd-tree's.
    const Scene s = test::random_soup(4000, 60);
    const KdTree tree = KdTree::build(s);
    const Box b = s.bounds();
    const Float3 centre = (b.lower + b.upper) * 0.5f, e = b.extent();
    std::mt19937 random(61);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    std::vector<Ray> rays;
    for (int o = 0; o < 400; ++o) {
        const Float3 origin =
            centre + Float3{e.x * 1e-5f * u(random), e.y * 1e-5f * u(random), e.z * 1e-5f * u(random)};
        for (int i = 0; i < 16; ++i) {
            const Float3 d{u(random), u(random), u(random)};
            rays.push_back(Ray{origin, 0.0f, d, kInfinity});
        }
    }
    std::shuffle(rays.begin(), rays.end(), random);
    StreamSettings whole;
    whole.bucket_order = false;
    const QueryCounters counters = expect_the_kd_trees_answers(s, tree, StreamTracer(tree, whole), rays, "one cell");
    // In buckets: the same answers, every ray through the wide BVH.
    const QueryCounters buckets = expect_the_kd_trees_answers(s, tree, StreamTracer(tree), rays, "one cell, buckets");
    EXPECT_EQ(buckets.stream.bucket_ordered_rays, 2 * rays.size());
    EXPECT_GT(counters.stream.origin_group_rays, 2 * rays.size() * 3 / 4);
    EXPECT_EQ(counters.stream.origin_group_rays + counters.stream.single_rays + counters.stream.loose_group_rays,
              2 * rays.size());
}
