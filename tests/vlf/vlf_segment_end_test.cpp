// Issue 18's three "mismatches" of the room at l = 33 (AO along PSF directions): three identical
// rays that end on the floor. The library's watertight test (brute force, kd1, vlf: all the same
// kernel) computes the floor's t equal to the ray's tfar, bit for bit, and counts the hit
// (tnear <= t <= tfar); Embree computes t 2 ulp beyond tfar and does not; in exact arithmetic the
// crossing lies 1.2 ulp (1.4e-7) beyond tfar. vlf answers as brute force does; the comparison counts
// the disagreement as grazing (the segment ends within reach of the triangle one side hit, and the
// line crosses nothing on the segment away from its ends), not as a mismatch (as it did before).
// The scene here is the room's shell (its first 12 triangles: same box, so the same tile grid as the
// room's) and the ray is the bench's, bit for bit.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <vector>

#include "beamtrace/kdtree.hpp"
#include "beamtrace/vlf.hpp"
#include "common/triangle_reference.hpp"
#include "common/watertight_ray.hpp"
#include "oracle/comparison.hpp"
#include "oracle/embree_oracle.hpp"

using namespace beamtrace;

namespace {

// The room's walls, floor and ceiling (scenes::room(1), triangles 0 to 11; the floor is y = 0).
Scene room_shell() {
    const float h = 3.2f;
    const std::vector<Float3> v = {{0, 0, 0},  {0, h, 0},  {0, h, 9},  {0, 0, 9},
                                   {12, 0, 0}, {12, 0, 9}, {12, h, 9}, {12, h, 0}};
    const std::vector<std::uint32_t> i = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 0, 3, 5, 0, 5, 4,
                                          1, 7, 6, 1, 6, 2, 0, 4, 7, 0, 7, 1, 3, 2, 6, 3, 6, 5};
    return Scene(v, i);
}

// Ray 8141569 of `bench --scene room --mode ao --ao-dirs psf --ao-rays 16 --vlf-dirs 33` (also
// 8141570 and 8141581).
Ray ending_on_the_floor() {
    return Ray{{0x1.3b5824p+2f, 0x1.03b524p+0f, 0x1.543e98p-5f}, 0.0f, {0.0f, -0x1.52a7fap-1f, 0.75f}, 0x1.88a414p+0f};
}

TEST(VlfSegmentEnd, TheRoomsAoRayThatEndsOnTheFloor) {
    const Scene scene = room_shell();
    const Ray ray = ending_on_the_floor();
    ASSERT_EQ(ray.org.x, 4.927254676818848f);
    ASSERT_EQ(ray.org.y, 1.0144827365875244f);
    ASSERT_EQ(ray.org.z, 0.04153375327587128f);
    ASSERT_EQ(ray.dir.y, -0.6614378094673157f);
    ASSERT_EQ(ray.tfar, 1.5337536334991455f);
    const Box box = scene.bounds();
    ASSERT_EQ(box.upper.x, 12.0f);
    ASSERT_EQ(box.upper.y, 3.2f);
    ASSERT_EQ(box.upper.z, 9.0f);

    // The library's triangle test: the floor (triangle 5, corners (0,0,0), (12,0,9), (12,0,0)),
    // far from its edges, at t equal to tfar.
    const Hit brute = intersect_brute_force(scene, ray);
    ASSERT_TRUE(brute.hit());
    EXPECT_EQ(brute.triangle, 5u);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(brute.t), std::bit_cast<std::uint32_t>(ray.tfar));
    EXPECT_TRUE(occluded_brute_force(scene, ray));
    TriangleHit one;
    ASSERT_TRUE(intersect_triangle(make_watertight_ray(ray), scene.triangle(5), one));
    EXPECT_EQ(one.t, ray.tfar);

    // Exactly (double is exact to 1e-16 here): the plane y = 0 lies 1.2 ulp of tfar beyond it.
    const double exact = double(ray.org.y) / -double(ray.dir.y);
    const double ulp = double(std::nextafter(ray.tfar, 2.0f)) - double(ray.tfar);
    EXPECT_GT(exact, double(ray.tfar));
    EXPECT_LT(exact - double(ray.tfar), 1.5 * ulp);

    // Embree: t 2 ulp beyond tfar, so not occluded.
    const oracle::EmbreeOracle embree(scene);
    EXPECT_FALSE(embree.occluded1(ray));
    Ray longer = ray;
    longer.tfar = kInfinity;
    const Hit e = embree.intersect1(longer);
    ASSERT_TRUE(e.hit());
    EXPECT_EQ(e.triangle, 5u);
    EXPECT_GT(e.t, ray.tfar);
    EXPECT_LE(double(e.t) - double(ray.tfar), 2.0 * ulp);

    // vlf answers as brute force does, in every form of query, lazy or whole, for the l = 33
    // and others: single rays (both modes: the segment stays in one tile), packets, binned streams.
    Packet16 packet{};
    for (int i = 0; i < 16; ++i) packet.set_ray(i, ray);
    packet.active = 0xFFFFu;
    const std::vector<Packet16> packets(3, packet);
    for (const int l : {9, 33, 129}) {
        for (const bool eager : {false, true}) {
            SCOPED_TRACE("l = " + std::to_string(l) + (eager ? " eager" : " lazy"));
            VlfOptions o;
            o.directions = l;
            o.eager = eager;
            const VisibilityField field(scene, o);
            const Hit h = field.intersect(ray);
            EXPECT_EQ(h.triangle, brute.triangle);
            EXPECT_EQ(std::bit_cast<std::uint32_t>(h.t), std::bit_cast<std::uint32_t>(brute.t));
            EXPECT_TRUE(field.occluded(ray));
            EXPECT_TRUE(field.occluded(ray, VlfMode::fast));
            EXPECT_EQ(field.occluded(packet), 0xFFFFu);
            for (const VlfOrder order : {VlfOrder::input, VlfOrder::psf}) {
                std::vector<std::uint32_t> bits(packets.size(), 0);
                field.occluded(packets, bits, VlfMode::exact, order);
                for (const std::uint32_t b : bits) EXPECT_EQ(b, 0xFFFFu);
            }
        }
    }

    // The comparison: a hit where the segment ends, not a mismatch (before: mismatch).
    const double reach = 1e-5 * double(box.diagonal());  // the grazing distance
    EXPECT_LT((exact - double(ray.tfar)) * std::hypot(double(ray.dir.y), double(ray.dir.z)), reach / 100.0);
    EXPECT_EQ(oracle::classify_occlusion(scene, ray, true, false), oracle::Verdict::grazing);
    EXPECT_EQ(oracle::classify_occlusion(scene, ray, true, false, 5), oracle::Verdict::grazing);
    EXPECT_EQ(oracle::classify_hit(scene, ray, brute, Hit{}), oracle::Verdict::grazing);
    // A ray that stops earlier (1e-3, beyond reach) and were found occluded would still be a mismatch.
    Ray shorter = ray;
    shorter.tfar = ray.tfar - 1e-3f;
    EXPECT_FALSE(occluded_brute_force(scene, shorter));
    EXPECT_EQ(oracle::classify_occlusion(scene, shorter, true, false), oracle::Verdict::mismatch);
}

}  // namespace
