// Each class of the comparison constructed explicitly, the tally and its JSON.
#include "oracle/comparison.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "hand_scenes.hpp"
#include "oracle/comparison_json.hpp"
#include "oracle/embree_oracle.hpp"

namespace beamtrace::oracle {
namespace {

using test::cube;
using test::one_triangle;
using test::two_triangles;
using test::with_degenerates;

Ray make_ray(Float3 org, Float3 dir, float tnear = 0.0f, float tfar = kInfinity) { return Ray{org, tnear, dir, tfar}; }

const Hit kMiss{};

// one_triangle(): corners (0,0,1), (2,0,1), (0,2,1); box diagonal sqrt(8), so rays within
// 2.8e-5 of an edge graze. These rays come down the z axis.
const Ray kCentreRay = make_ray({0.5f, 0.5f, -2.0f}, {0, 0, 1});              // 0.5 from every edge
const Ray kJustOutside = make_ray({1.000005f, 1.000005f, -2.0f}, {0, 0, 1});  // 7e-6 beyond the hypotenuse
const Ray kFarOutside = make_ray({1.001f, 1.001f, -2.0f}, {0, 0, 1});         // 1.4e-3 beyond it

TEST(Comparison, AgreeWhenBothMissOrHitTheSameTriangleAtTheSameT) {
    const Scene s = one_triangle();
    EXPECT_EQ(classify_hit(s, kFarOutside, kMiss, kMiss), Verdict::agree);
    EXPECT_EQ(classify_hit(s, kCentreRay, Hit{3.0f, 0, 0.25f, 0.25f}, Hit{3.0001f, 0, 0.25f, 0.25f}), Verdict::agree);
    // Tolerance 1e-4 * max(1, t): absolute below t = 1, relative above.
    EXPECT_EQ(classify_hit(s, kCentreRay, Hit{0.01f, 0}, Hit{0.01f + 0.9e-4f, 0}), Verdict::agree);
    EXPECT_EQ(classify_hit(s, kCentreRay, Hit{1000.0f, 0}, Hit{1000.05f, 0}), Verdict::agree);
    EXPECT_EQ(classify_hit(s, kCentreRay, Hit{1000.0f, 0}, Hit{1000.2f, 0}), Verdict::mismatch);
    EXPECT_EQ(classify_hit(s, kCentreRay, Hit{0.01f, 0}, Hit{0.01f + 2e-4f, 0}), Verdict::mismatch);
}

TEST(Comparison, TiesOnASharedEdge) {
    const Scene s = two_triangles();
    const Ray on_diagonal = make_ray({0.5f, 0.5f, 1.0f}, {0, 0, -1});
    const EmbreeOracle o(s);
    const Hit embree = o.intersect1(on_diagonal);
    ASSERT_TRUE(embree.hit());
    EXPECT_NEAR(embree.t, 1.0f, 1e-6f);
    const Hit other{1.0f, embree.triangle == 0 ? 1u : 0u, 0.5f, 0.0f};
    EXPECT_EQ(classify_hit(s, on_diagonal, other, embree), Verdict::ties);
    EXPECT_EQ(classify_hit(s, on_diagonal, embree, embree), Verdict::agree);
    // Shared vertex of the cube: a ray at a corner may report any of the faces meeting there.
    const Scene c = cube();
    const Ray at_corner = make_ray({2.0f, 2.0f, 2.0f}, {-1, -1, -1});
    EXPECT_EQ(classify_hit(c, at_corner, Hit{1.0f, 3}, Hit{1.0f, 7}), Verdict::ties);
}

TEST(Comparison, GrazingNearAnEdgeOfATriangleInvolved) {
    const Scene s = one_triangle();
    const EmbreeOracle o(s);
    ASSERT_FALSE(o.intersect1(kJustOutside).hit());  // the exact ray misses
    EXPECT_EQ(classify_hit(s, kJustOutside, Hit{3.0f, 0, 0.5f, 0.5f}, kMiss), Verdict::grazing);
    EXPECT_EQ(classify_hit(s, kJustOutside, kMiss, Hit{3.0f, 0, 0.5f, 0.5f}), Verdict::grazing);
    // Same triangle, t off: still grazing if the ray passes near its edge.
    EXPECT_EQ(classify_hit(s, kJustOutside, Hit{3.0f, 0}, Hit{3.5f, 0}), Verdict::grazing);
    // Two faces of the cube sharing an edge, different t: grazing along that edge.
    const Scene c = cube();
    const Ray along_edge = make_ray({1.0f + 1e-6f, -5.0f, 1.0f}, {0, 1, 0});
    EXPECT_EQ(classify_hit(c, along_edge, Hit{4.0f, 4}, Hit{5.5f, 10}), Verdict::grazing);
}

// The segment ends (at tfar or tnear) within rounding of a triangle, far from its edges: the float t
// of the two tracers may fall on either side of the end (room, AO along PSF directions: our
// watertight t equal to tfar, Embree's 2 ulp beyond it, the exact crossing 1.2 ulp beyond).
TEST(Comparison, GrazingWhereTheSegmentEndsOnATriangle) {
    const Scene s = one_triangle();                                                   // reach 2.8e-5
    const Ray ends_on_it = make_ray({0.5f, 0.5f, -2.0f}, {0, 0, 1}, 0.0f, 2.99999f);  // 1e-5 short of it
    EXPECT_EQ(classify_hit(s, ends_on_it, Hit{2.99999f, 0}, kMiss), Verdict::grazing);
    EXPECT_EQ(classify_hit(s, ends_on_it, kMiss, Hit{2.99999f, 0}), Verdict::grazing);
    EXPECT_EQ(classify_occlusion(s, ends_on_it, true, false), Verdict::grazing);
    EXPECT_EQ(classify_occlusion(s, ends_on_it, false, true), Verdict::grazing);
    EXPECT_EQ(classify_occlusion(s, ends_on_it, false, true, 0), Verdict::grazing);
    const Ray starts_on_it = make_ray({0.5f, 0.5f, -2.0f}, {0, 0, 1}, 3.00001f, 10.0f);  // 1e-5 beyond it
    EXPECT_EQ(classify_hit(s, starts_on_it, Hit{3.00001f, 0}, kMiss), Verdict::grazing);
    EXPECT_EQ(classify_occlusion(s, starts_on_it, true, false), Verdict::grazing);
    // Not when the end is farther than the reach.
    const Ray ends_short = make_ray({0.5f, 0.5f, -2.0f}, {0, 0, 1}, 0.0f, 2.999f);  // 1e-3 short
    EXPECT_EQ(classify_hit(s, ends_short, Hit{3.0f, 0}, kMiss), Verdict::mismatch);
    EXPECT_EQ(classify_occlusion(s, ends_short, true, false), Verdict::mismatch);
    EXPECT_EQ(classify_occlusion(s, ends_short, false, true, 0), Verdict::mismatch);
    // Not when the segment crosses a triangle away from its ends: the cube's front face (z = -1,
    // triangle 8 at t = 3) inside a ray that ends on its back face (z = 1, triangle 11 at t = 5).
    const Scene c = cube();
    const Ray ends_on_back = make_ray({0.1f, 0.2f, -4.0f}, {0, 0, 1}, 0.0f, 4.99999f);
    EXPECT_EQ(classify_occlusion(c, ends_on_back, true, false), Verdict::mismatch);
    EXPECT_EQ(classify_occlusion(c, ends_on_back, false, true, 11), Verdict::mismatch);
    EXPECT_EQ(classify_hit(c, ends_on_back, Hit{5.0f, 11}, kMiss), Verdict::mismatch);
    EXPECT_EQ(classify_hit(c, ends_on_back, kMiss, Hit{5.0f, 11}), Verdict::mismatch);
    // Without the front face's crossing (a ray starting just past it) the back face's end explains it.
    const Ray past_front = make_ray({0.1f, 0.2f, -4.0f}, {0, 0, 1}, 3.5f, 4.99999f);
    EXPECT_EQ(classify_occlusion(c, past_front, true, false), Verdict::grazing);
    EXPECT_EQ(classify_hit(c, past_front, Hit{5.0f, 11}, kMiss), Verdict::grazing);
    // A hit on a triangle that is not the one at the end: mismatch, whatever lies at the end.
    EXPECT_EQ(classify_hit(c, past_front, Hit{3.0f, 8}, kMiss), Verdict::mismatch);
    EXPECT_EQ(classify_occlusion(c, past_front, true, false, 8), Verdict::mismatch);
    // Both sides hit, at different t: the ends are not asked.
    EXPECT_EQ(classify_hit(c, past_front, Hit{5.0f, 11}, Hit{4.0f, 11}), Verdict::mismatch);
}

TEST(Comparison, MismatchEverywhereElse) {
    const Scene s = one_triangle();
    EXPECT_EQ(classify_hit(s, kCentreRay, kMiss, Hit{3.0f, 0, 0.25f, 0.25f}), Verdict::mismatch);
    EXPECT_EQ(classify_hit(s, kFarOutside, Hit{3.0f, 0, 0.5f, 0.5f}, kMiss), Verdict::mismatch);
    // The near edge lies beyond the end of the ray's segment.
    const Ray short_ray = make_ray({1.000005f, 1.000005f, -2.0f}, {0, 0, 1}, 0.0f, 1.0f);
    EXPECT_EQ(classify_hit(s, short_ray, Hit{3.0f, 0}, kMiss), Verdict::mismatch);
    // Front face against back face of the cube, far from every edge.
    const Scene c = cube();
    const Ray through = make_ray({0.1f, 0.2f, -4.0f}, {0, 0, 1});
    EXPECT_EQ(classify_hit(c, through, Hit{3.0f, 8}, Hit{5.0f, 10}), Verdict::mismatch);
    // Different triangles at different t even though one of them is the right answer.
    EXPECT_EQ(classify_hit(c, through, Hit{5.0f, 10}, Hit{3.0f, 8}), Verdict::mismatch);
}

TEST(Comparison, HitsOnDegenerateOrUnknownTrianglesAreMismatches) {
    const Scene s = with_degenerates();
    const Ray along_degenerate = make_ray({-1.0f, 0.0f, 1.0f}, {1, 0, 0});
    EXPECT_EQ(classify_hit(s, along_degenerate, Hit{1.0f, 0}, kMiss), Verdict::mismatch);
    EXPECT_EQ(classify_hit(s, along_degenerate, Hit{1.0f, 0}, Hit{1.0f, 0}), Verdict::mismatch);
    EXPECT_EQ(classify_hit(s, along_degenerate, Hit{1.0f, 99}, kMiss), Verdict::mismatch);
    EXPECT_EQ(classify_occlusion(s, along_degenerate, true, false, 0), Verdict::mismatch);
    EXPECT_EQ(classify_occlusion(s, along_degenerate, true, false, 99), Verdict::mismatch);
    // Without a hint, the brute force skips degenerate triangles: the good triangle's edges are
    // at z = 0, one unit below this ray.
    EXPECT_EQ(classify_occlusion(s, along_degenerate, true, false), Verdict::mismatch);
}

TEST(Comparison, OcclusionClasses) {
    const Scene s = one_triangle();
    EXPECT_EQ(classify_occlusion(s, kCentreRay, true, true, 0), Verdict::agree);
    EXPECT_EQ(classify_occlusion(s, kFarOutside, false, false), Verdict::agree);
    // With the hit triangle known.
    EXPECT_EQ(classify_occlusion(s, kJustOutside, true, false, 0), Verdict::grazing);
    EXPECT_EQ(classify_occlusion(s, kCentreRay, false, true, 0), Verdict::mismatch);
    // Unknown: brute force over the scene.
    EXPECT_EQ(classify_occlusion(s, kJustOutside, false, true), Verdict::grazing);
    EXPECT_EQ(classify_occlusion(s, kCentreRay, true, false), Verdict::mismatch);
    EXPECT_EQ(classify_occlusion(s, kFarOutside, true, false), Verdict::mismatch);
    const Ray short_ray = make_ray({1.000005f, 1.000005f, -2.0f}, {0, 0, 1}, 0.0f, 1.0f);
    EXPECT_EQ(classify_occlusion(s, short_ray, true, false), Verdict::mismatch);
    // In the cube the brute force finds the edge the ray runs along.
    const Scene c = cube();
    const Ray along_edge = make_ray({1.0f + 1e-6f, -5.0f, 1.0f}, {0, 1, 0});
    EXPECT_EQ(classify_occlusion(c, along_edge, true, false), Verdict::grazing);
    const Ray through = make_ray({0.1f, 0.2f, -4.0f}, {0, 0, 1});
    EXPECT_EQ(classify_occlusion(c, through, false, true), Verdict::mismatch);
}

TEST(Comparison, TallyCountsAndKeepsTheLowestMismatches) {
    Tally t;
    const Ray r = kCentreRay;
    for (std::uint64_t i = 0; i < 50; ++i) t.add(Verdict::mismatch, 100 - i, r, Hit{1.0f, 0}, kMiss);
    t.add(Verdict::agree, 1, r, kMiss, kMiss);
    t.add(Verdict::ties, 2, r, Hit{1.0f, 0}, Hit{1.0f, 1});
    t.add(Verdict::grazing, 3, r, true, false);
    t.add(Verdict::mismatch, 4, r, true, false);
    EXPECT_EQ(t.agree, 1u);
    EXPECT_EQ(t.ties, 1u);
    EXPECT_EQ(t.grazing, 1u);
    EXPECT_EQ(t.mismatch, 51u);
    EXPECT_EQ(t.total(), 54u);
    EXPECT_EQ(t.count(Verdict::mismatch), 51u);
    ASSERT_EQ(t.examples.size(), Tally::kMaxExamples);
    EXPECT_EQ(t.examples[0].ray_index, 4u);
    EXPECT_TRUE(t.examples[0].occlusion);
    EXPECT_TRUE(t.examples[0].ours_occluded);
    EXPECT_EQ(t.examples[1].ray_index, 51u);
    EXPECT_EQ(t.examples.back().ray_index, 69u);
    EXPECT_FALSE(t.examples[1].occlusion);
    EXPECT_EQ(t.examples[1].ours.triangle, 0u);

    // Merging in either order gives the same tally.
    Tally a, b;
    for (std::uint64_t i = 0; i < 30; ++i) a.add(Verdict::mismatch, 2 * i, r, kMiss, Hit{1.0f, 0});
    for (std::uint64_t i = 0; i < 30; ++i) b.add(Verdict::mismatch, 2 * i + 1, r, kMiss, Hit{1.0f, 0});
    b.add(Verdict::agree);
    Tally ab = a, ba = b;
    ab += b;
    ba += a;
    EXPECT_EQ(ab.mismatch, 60u);
    EXPECT_EQ(ab.agree, 1u);
    ASSERT_EQ(ab.examples.size(), ba.examples.size());
    for (std::size_t i = 0; i < ab.examples.size(); ++i) {
        EXPECT_EQ(ab.examples[i].ray_index, i);
        EXPECT_EQ(ba.examples[i].ray_index, i);
    }
}

TEST(Comparison, RecordClassifiesAndAdds) {
    const Scene s = one_triangle();
    Tally t;
    EXPECT_EQ(t.record_hit(s, 0, kCentreRay, Hit{3.0f, 0}, Hit{3.0f, 0}), Verdict::agree);
    EXPECT_EQ(t.record_hit(s, 1, kJustOutside, Hit{3.0f, 0}, kMiss), Verdict::grazing);
    EXPECT_EQ(t.record_hit(s, 2, kCentreRay, kMiss, Hit{3.0f, 0}), Verdict::mismatch);
    EXPECT_EQ(t.record_occlusion(s, 3, kCentreRay, false, true, 0), Verdict::mismatch);
    EXPECT_EQ(t.agree, 1u);
    EXPECT_EQ(t.grazing, 1u);
    EXPECT_EQ(t.mismatch, 2u);
    ASSERT_EQ(t.examples.size(), 2u);
    EXPECT_EQ(summary(t), "agree 1 ties 0 grazing 1 mismatch 2 (of 4)");
}

TEST(Comparison, TallyAsJson) {
    const Scene s = one_triangle();
    Tally t;
    t.record_hit(s, 7, kCentreRay, kMiss, Hit{3.0f, 0, 0.25f, 0.25f});
    t.record_occlusion(s, 9, kCentreRay, true, false, 0);
    t.add(Verdict::ties);
    const nlohmann::json counts = counts_json(t);
    EXPECT_EQ(counts, nlohmann::json::parse(R"({"agree":0,"ties":1,"grazing":0,"mismatch":2})"));
    const nlohmann::json all = to_json(t);
    EXPECT_EQ(all["total"], 3);
    ASSERT_EQ(all["examples"].size(), 2u);
    const auto& e = all["examples"][0];
    EXPECT_EQ(e["ray_index"], 7);
    EXPECT_TRUE(e["ours"]["triangle"].is_null());
    EXPECT_EQ(e["oracle"]["triangle"], 0);
    EXPECT_FLOAT_EQ(e["oracle"]["t"].get<float>(), 3.0f);
    EXPECT_TRUE(e["ray"]["tfar"].is_null());  // infinity
    EXPECT_EQ(all["examples"][1]["ours_occluded"], true);
    EXPECT_EQ(all["examples"][1]["oracle_occluded"], false);
    EXPECT_EQ(to_string(Verdict::grazing), std::string("grazing"));
}

}  // namespace
}  // namespace beamtrace::oracle
