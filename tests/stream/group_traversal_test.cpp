// The masked group traversal answers every lane as the single-ray traversal does (its reference):
// occlusion exactly, closest hits at the same distance bit for bit (the same triangle, or another at
// exactly that distance), on scenes shaped to reach the kd-tree's special cases: one-origin groups
// (what the stream tracer makes), scattered rays, rays inside split planes, segments that end on (or
// an ulp or a few around) the planes of their origin's path, inactive lanes and rays that describe no
// segment.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/kdtree.hpp"
#include "common/access.hpp"
#include "kdtree/ray_traversal.hpp"
#include "simd/dispatch.hpp"
#include "simd/isa.hpp"
#include "stream/group_traversal.hpp"
#include "../kdtree/test_scenes.hpp"

using namespace beamtrace;

namespace {

// Groups of 16 rays from the rays given: one-origin groups (each ray's origin with the next 15
// rays' directions), the rays as they come, and both with lanes switched off.
std::vector<Packet16> groups_of(const std::vector<Ray>& rays, unsigned seed) {
    std::mt19937 random(seed);
    std::vector<Packet16> groups;
    for (std::size_t b = 0; b + 16 <= rays.size(); b += 16) {
        Packet16 same, mixed;
        for (int i = 0; i < 16; ++i) {
            Ray r = rays[b + std::size_t(i)];
            mixed.set_ray(i, r);
            r.org = rays[b].org;
            same.set_ray(i, r);
        }
        same.active = mixed.active = 0xFFFFu;
        groups.push_back(same);
        groups.push_back(mixed);
        same.active = mixed.active = random() & 0xFFFFu;
        groups.push_back(same);
        groups.push_back(mixed);
    }
    return groups;
}

std::string describe(const Ray& r, const Hit& want, const Hit& got) {
    char text[320];
    std::snprintf(text, sizeof text, "ray org (%a, %a, %a) dir (%a, %a, %a) [%a, %a]: single ray t %a triangle %u, group t %a triangle %u",
                  r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tnear, r.tfar, want.t, want.triangle, got.t, got.triangle);
    return text;
}

void expect_single_ray_answers(const KdTree& tree, const std::vector<Packet16>& groups, const std::string& what) {
    const KdTree::Impl& kd = detail::Access::impl(tree);
    int compared = 0, hits = 0;
    for (std::size_t g = 0; g < groups.size(); ++g) {
        const Packet16& p = groups[g];
        PacketHits16 got;
        std::uint32_t occluded = 0xDEADu;
        stream::trace_group<false, false>(kd, p, &got, nullptr, nullptr);
        stream::trace_group<true, false>(kd, p, nullptr, &occluded, nullptr);
        QueryCounters counters;
        PacketHits16 counted;
        std::uint32_t counted_occluded = 0;
        stream::trace_group<false, true>(kd, p, &counted, nullptr, &counters);
        stream::trace_group<true, true>(kd, p, nullptr, &counted_occluded, &counters);
        EXPECT_EQ(counted_occluded, occluded) << what << " group " << g;
        for (int i = 0; i < 16; ++i) {
            const bool on = (p.active >> i) & 1u;
            const Ray r = p.ray(i);
            const Hit want = on ? kdtree::intersect_one(kd, r) : Hit{};
            const bool want_occluded = on && kdtree::occluded_one(kd, r);
            const Hit h = got.hit(i);
            ASSERT_EQ(((occluded >> i) & 1u) != 0, want_occluded) << what << " group " << g << " lane " << i;
            ASSERT_EQ(h.hit(), want.hit()) << what << " group " << g << " lane " << i << ": " << describe(r, want, h);
            ASSERT_EQ(counted.hit(i).triangle, h.triangle);
            if (!want.hit()) continue;
            ++hits;
            ASSERT_EQ(h.t, want.t) << what << " group " << g << " lane " << i << ": " << describe(r, want, h);
            if (h.triangle == want.triangle) {
                EXPECT_EQ(h.u, want.u);
                EXPECT_EQ(h.v, want.v);
            }
            ++compared;
        }
    }
    EXPECT_GT(compared, 0) << what;
    EXPECT_GT(hits, 0) << what;
}

}  // namespace

TEST(StreamGroupTraversal, AnswersAsTheSingleRayTraversalOnSoup) {
    const Scene scene = test::random_soup(3000, 1);
    const KdTree tree = KdTree::build(scene);
    expect_single_ray_answers(tree, groups_of(test::random_rays(scene.bounds(), 4000, 2), 3), "soup");
}

TEST(StreamGroupTraversal, AnswersAsTheSingleRayTraversalInABoxedRoom) {
    const Scene scene = test::stacked_boxes(60, 4);
    const KdTree tree = KdTree::build(scene);
    expect_single_ray_answers(tree, groups_of(test::random_rays(scene.bounds(), 4000, 5), 6), "boxes");
    // Rays in split planes, with zero and -0 direction components.
    expect_single_ray_answers(tree, groups_of(test::axis_rays(scene, 4000, 7), 8), "boxes, axis rays");
}

TEST(StreamGroupTraversal, AnswersAsTheSingleRayTraversalOnAPlane) {
    const Scene scene = test::single_plane(24);
    const KdTree tree = KdTree::build(scene);
    expect_single_ray_answers(tree, groups_of(test::axis_rays(scene, 2000, 9), 10), "plane, axis rays");
    expect_single_ray_answers(tree, groups_of(test::random_rays(scene.bounds(), 2000, 11), 12), "plane");
}

// One-origin groups whose segments end on, just before or just beyond the split planes of their
// origin's path through the tree (the planes the group passes without a step when no lane reaches
// them: GroupTrace::make_reach): lane i ends k ulps of t around a plane of the path, k in -4..4.
std::vector<Packet16> groups_ending_at_planes(const KdTree& tree, int count, unsigned seed) {
    const KdTree::Impl& kd = detail::Access::impl(tree);
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), spread(-1.0f, 1.0f);
    const Box& box = kd.bounds;
    std::vector<Packet16> groups;
    while (int(groups.size()) < count) {
        Float3 o;
        for (int k = 0; k < 3; ++k) o[k] = box.lower[k] + (box.upper[k] - box.lower[k]) * (0.05f + 0.9f * unit(random));
        std::vector<std::pair<int, float>> planes;
        for (std::uint32_t index = 0; !kd.nodes[index].is_leaf();) {
            const KdNode& node = kd.nodes[index];
            if (o[node.axis()] != node.split) planes.emplace_back(node.axis(), node.split);
            index = o[node.axis()] < node.split ? index + 1 : node.upper_child();
        }
        if (planes.empty()) continue;
        Packet16 p;
        for (int i = 0; i < 16; ++i) {
            const auto [axis, split] = planes[random() % planes.size()];
            Float3 d{spread(random), spread(random), spread(random)};
            d[axis] = (split > o[axis] ? 1.0f : -1.0f) * (0.2f + unit(random));
            float t = (split - o[axis]) / d[axis];
            for (int k = int(random() % 9) - 4; k != 0; k += k > 0 ? -1 : 1)
                t = std::nextafter(t, k > 0 ? INFINITY : 0.0f);
            p.set_ray(i, Ray{o, 0.0f, d, t});
        }
        p.active = groups.size() % 3 == 2 ? (random() & 0xFFFFu) | 1u : 0xFFFFu;
        groups.push_back(p);
    }
    return groups;
}

TEST(StreamGroupTraversal, SegmentsEndingAtTheOriginsPlanesAnswerAsTheSingleRayTraversal) {
    const Scene soup = test::random_soup(3000, 41), boxes = test::stacked_boxes(60, 4);
    for (const Scene* scene : {&soup, &boxes}) {
        const KdTree tree = KdTree::build(*scene);
        const std::vector<Packet16> groups = groups_ending_at_planes(tree, 600, 42);
        expect_single_ray_answers(tree, groups, scene == &soup ? "soup, ends at planes" : "boxes, ends at planes");
        // The planes beyond every lane are passed without a step, and some lanes reach the planes.
        QueryCounters counters;
        std::uint32_t occluded = 0;
        for (const Packet16& p : groups)
            stream::trace_group<true, true>(detail::Access::impl(tree), p, nullptr, &occluded, &counters);
        EXPECT_GT(counters.stream.group_unreached_planes, 0u);
        EXPECT_GT(counters.stream.group_steps, 0u);
    }
}

TEST(StreamGroupTraversal, RaysThatDescribeNoSegmentReportNothing) {
    const Scene scene = test::random_soup(500, 13);
    const KdTree tree = KdTree::build(scene);
    const KdTree::Impl& kd = detail::Access::impl(tree);
    std::vector<Ray> rays = test::random_rays(scene.bounds(), 16, 14);
    rays[0].dir = Float3{0, 0, 0};
    rays[1].org.x = NAN;
    rays[2].tnear = 5.0f;
    rays[2].tfar = 1.0f;
    rays[3].dir.y = INFINITY;
    Packet16 p;
    for (int i = 0; i < 16; ++i) p.set_ray(i, rays[std::size_t(i)]);
    p.active = 0xFFFFu;
    PacketHits16 hits;
    std::uint32_t occluded = 0;
    stream::trace_group<false, false>(kd, p, &hits, nullptr, nullptr);
    stream::trace_group<true, false>(kd, p, nullptr, &occluded, nullptr);
    for (int i = 0; i < 4; ++i) {
        EXPECT_FALSE(hits.hit(i).hit()) << i;
        EXPECT_EQ((occluded >> i) & 1u, 0u) << i;
    }
    for (int i = 4; i < 16; ++i) {
        EXPECT_EQ(hits.hit(i).triangle, kdtree::intersect_one(kd, p.ray(i)).triangle);
        EXPECT_EQ(((occluded >> i) & 1u) != 0, kdtree::occluded_one(kd, p.ray(i)));
    }
}

TEST(StreamGroupTraversal, EveryInstructionSetGivesTheSameAnswersBitForBit) {
    // The traversal at 4, 8 and 16 lanes a step (SSE4.2, AVX2, AVX-512): every lane's hit (distance,
    // triangle, u, v), occlusion bits and counts equal the SSE4.2 kernels', on soup, boxes with rays
    // in split planes, and a plane; one-origin and scattered groups, some lanes switched off.
    const Scene soup = test::random_soup(3000, 31), boxes = test::stacked_boxes(60, 4), plane = test::single_plane(24);
    const KdTree trees[] = {KdTree::build(soup), KdTree::build(boxes), KdTree::build(plane)};
    const std::vector<Packet16> groups[] = {groups_of(test::random_rays(soup.bounds(), 2000, 32), 33),
                                            groups_of(test::axis_rays(boxes, 2000, 34), 35),
                                            groups_of(test::random_rays(plane.bounds(), 2000, 36), 37)};
    const stream::GroupKernels& ref = simd::select<stream::GroupKernels>(Isa::sse42);
    int checked = 0;
    for (Isa isa : {Isa::avx2, Isa::avx512}) {
        if (!isa_available(isa)) {
            std::printf("(%s not available on this CPU: not compared)\n", isa_name(isa));
            continue;
        }
        const stream::GroupKernels& k = simd::select<stream::GroupKernels>(isa);
        ASSERT_EQ(k.isa, isa);
        for (int s = 0; s < 3; ++s) {
            const KdTree::Impl& kd = detail::Access::impl(trees[s]);
            for (std::size_t g = 0; g < groups[s].size(); ++g) {
                const Packet16& p = groups[s][g];
                PacketHits16 want, got;
                std::uint32_t want_occluded = 0, got_occluded = 0;
                QueryCounters want_counts, got_counts;
                ref.trace[0][1](kd, p, &want, nullptr, &want_counts);
                k.trace[0][1](kd, p, &got, nullptr, &got_counts);
                ref.trace[1][1](kd, p, nullptr, &want_occluded, &want_counts);
                k.trace[1][1](kd, p, nullptr, &got_occluded, &got_counts);
                ASSERT_EQ(got_occluded, want_occluded) << isa_name(isa) << " scene " << s << " group " << g;
                ASSERT_EQ(std::memcmp(&got, &want, sizeof(PacketHits16)), 0)
                    << isa_name(isa) << " scene " << s << " group " << g;
                ASSERT_EQ(got_counts.stream.group_steps, want_counts.stream.group_steps);
                ASSERT_EQ(got_counts.stream.group_leaves, want_counts.stream.group_leaves);
                ASSERT_EQ(got_counts.stream.group_unreached_planes, want_counts.stream.group_unreached_planes);
                ASSERT_EQ(got_counts.triangle_tests, want_counts.triangle_tests);
                ++checked;
            }
        }
    }
    if (isa_available(Isa::avx2)) {
        EXPECT_GT(checked, 0);
    }
}
