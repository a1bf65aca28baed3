// Beams (section 3.3, condition (3) of section 4.1): from packets, from rays with different origins,
// from the corner rays of a pinhole rectangle; coherence; merging. A beam is right when, for every
// ray it describes and every axis-aligned plane, plane_range and plane_t contain the exact (double
// precision) intersection of the ray's line with the plane.
#include <gtest/gtest.h>

#include <cmath>

#include "hand_tree.hpp"

using namespace beamtrace;
using namespace beamtrace::mlrta;
using namespace beamtrace::mlrta::test;

namespace {

const Box kScene{{-4, -4, -4}, {4, 4, 4}};

bool contains(Interval i, double x) { return double(i.lo) <= x && x <= double(i.hi); }

// Every plane x_k = p (ahead of the starts, behind them, through them) bounds the ray's crossing.
::testing::AssertionResult beam_bounds_ray(const Beam& b, const Ray& r, Rng& rng, int planes = 12) {
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < planes; ++i) {
            const float p = i == 0 ? r.org[k] : uniform(rng, -3.0f, 3.0f);
            for (int j = 0; j < 3; ++j) {
                if (j == k) continue;
                const double exact = plane_coordinate(r, k, p, j);
                const Interval range = b.plane_range(k, p, j);
                if (!contains(range, exact))
                    return ::testing::AssertionFailure()
                           << "plane x" << k << " = " << p << ": coordinate " << j << " " << exact << " outside ["
                           << range.lo << ", " << range.hi << "]";
            }
            const double t = plane_parameter(r, k, p, b.main_axis);
            const Interval range = b.plane_t(k, p);
            if (!contains(range, t))
                return ::testing::AssertionFailure() << "plane x" << k << " = " << p << ": t' " << t << " outside ["
                                                     << range.lo << ", " << range.hi << "]";
        }
    // The segment's length along the main axis (rounded as the beam rounds it: the culling tests
    // widen the plane parameters they compare it with by far more than one rounding).
    const float length = (r.tfar - r.tnear) * std::fabs(r.dir[b.main_axis]);
    if (!contains(b.length, length)) return ::testing::AssertionFailure() << "length " << length << " outside";
    return ::testing::AssertionSuccess();
}

Float3 random_direction(Rng& rng, const int sign[3]) {
    Float3 d;
    for (int k = 0; k < 3; ++k) d[k] = float(sign[k]) * uniform(rng, 0.05f, 1.0f);
    return d;
}

}  // namespace

TEST(MlrtaBeam, FromPacketBoundsEveryActiveRay) {
    Rng rng(1);
    for (int trial = 0; trial < 200; ++trial) {
        const int sign[3] = {rng() % 2 ? 1 : -1, rng() % 2 ? 1 : -1, rng() % 2 ? 1 : -1};
        std::vector<Ray> rays = bundle(rng, 16, {uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)}, 0.2f,
                                       random_direction(rng, sign), 0.3f);
        for (Ray& r : rays) {
            r.tnear = rng() % 2 ? 0.0f : uniform(rng, 0.0f, 0.5f);
            r.tfar = rng() % 3 ? uniform(rng, 1.0f, 5.0f) : kInfinity;
        }
        const std::uint32_t active = (trial % 4 == 0) ? 0xFFFFu : std::uint32_t(rng() & 0xFFFFu) | 1u;
        Packet16 packet = packet_of(rays, active);
        for (int i = 0; i < 16; ++i)
            if (!((active >> i) & 1u)) {  // inactive lanes hold garbage of the wrong sign: ignored
                packet.dir_x[i] = -packet.dir_x[i];
                packet.org_y[i] = NAN;
            }
        Beam b;
        b.set_scene_scale(kScene);
        b.add(packet);
        ASSERT_FALSE(b.empty);
        ASSERT_TRUE(b.coherent);
        ASSERT_EQ(b.rays, std::uint32_t(__builtin_popcount(active)));
        for (int k = 0; k < 3; ++k) ASSERT_EQ(b.sign[k], sign[k]);
        for (int i = 0; i < 16; ++i) {
            if (!((active >> i) & 1u)) continue;
            const Ray& r = rays[std::size_t(i)];
            const Float3 start = r.org + r.dir * r.tnear;
            for (int k = 0; k < 3; ++k) {
                ASSERT_LE(b.starts.lower[k], start[k]);
                ASSERT_GE(b.starts.upper[k], start[k]);
                for (int j = 0; j < 3; ++j) ASSERT_TRUE(contains(b.slope[k][j], double(r.dir[j] / r.dir[k])));
            }
            ASSERT_TRUE(beam_bounds_ray(b, r, rng)) << "trial " << trial << " lane " << i;
        }
    }
}

TEST(MlrtaBeam, FromRaysWithDifferentOriginsBoundsEveryRay) {
    Rng rng(2);
    for (int trial = 0; trial < 200; ++trial) {
        const int sign[3] = {rng() % 2 ? 1 : -1, rng() % 2 ? 1 : -1, rng() % 2 ? 1 : -1};
        // Origins far apart (a reflection off a large flat mirror), directions within a wide cone.
        const std::vector<Ray> rays =
            bundle(rng, 1 + int(rng() % 40), {0, 0, 0}, 2.0f, random_direction(rng, sign), 0.9f);
        const Beam b = beam_of(rays, &kScene);
        ASSERT_TRUE(b.coherent);
        ASSERT_EQ(b.rays, rays.size());
        for (const Ray& r : rays) ASSERT_TRUE(beam_bounds_ray(b, r, rng)) << "trial " << trial;
    }
}

TEST(MlrtaBeam, PinholeCornersBoundEveryInteriorRay) {
    Rng rng(3);
    int checked = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const Float3 eye{uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2)};
        const Float3 base{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
        const Float3 du = Float3{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)} * 0.01f;
        const Float3 dv = Float3{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)} * 0.01f;
        const float x0 = uniform(rng, -40, 40), y0 = uniform(rng, -40, 40);
        const float x1 = x0 + uniform(rng, 0, 30), y1 = y0 + uniform(rng, 0, 30);
        const Beam b = pinhole_beam(eye, base, du, dv, x0, y0, x1, y1);
        ASSERT_EQ(b.rays, 4u);
        ASSERT_EQ(b.starts.lower, eye);
        ASSERT_EQ(b.starts.upper, eye);
        if (!b.coherent) continue;  // the rectangle straddles a sign change: nothing to bound
        ASSERT_EQ(b.length.hi, kInfinity);
        for (int i = 0; i < 40; ++i) {
            const float x = i < 4 ? (i % 2 ? x1 : x0) : uniform(rng, x0, x1);
            const float y = i < 4 ? (i / 2 ? y1 : y0) : uniform(rng, y0, y1);
            const Ray r{eye, 0.0f, base + du * x + dv * y, kInfinity};
            ASSERT_TRUE(beam_bounds_ray(b, r, rng, 4)) << "trial " << trial << " pixel " << x << ", " << y;
            ++checked;
        }
    }
    EXPECT_GT(checked, 4000);
}

TEST(MlrtaBeam, MergedPinholeBeamsOfDifferentEyesBoundEveryInteriorRay) {
    Rng rng(4);
    const Float3 base{0.3f, -0.4f, 1.0f}, du{0.002f, 0.0f, 0.0001f}, dv{0.0f, 0.002f, -0.0001f};
    Beam merged;
    std::vector<Float3> eyes;
    for (int e = 0; e < 3; ++e) {
        eyes.push_back({uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)});
        const Beam b = pinhole_beam(eyes.back(), base, du, dv, 0, 0, 31, 31);
        ASSERT_TRUE(b.coherent);
        merged.merge(b);
    }
    ASSERT_TRUE(merged.coherent);
    ASSERT_EQ(merged.rays, 12u);
    for (const Float3& eye : eyes)
        for (int i = 0; i < 200; ++i) {
            const Ray r{eye, 0.0f, base + du * uniform(rng, 0, 31) + dv * uniform(rng, 0, 31), kInfinity};
            ASSERT_TRUE(beam_bounds_ray(merged, r, rng, 4));
        }
}

TEST(MlrtaBeam, IncoherentWhenSignsDifferOrAComponentIsZero) {
    const Ray a{{0, 0, 0}, 0.0f, {0.5f, 0.2f, 1.0f}, kInfinity};
    {
        Beam b;
        b.add(a);
        EXPECT_TRUE(b.coherent);
        EXPECT_EQ(b.main_axis, 2);
    }
    for (int k = 0; k < 3; ++k)
        for (float v : {0.0f, -0.0f, -0.1f}) {
            Ray r = a;
            r.dir[k] = v;
            Beam after;  // the odd ray last
            after.add(a);
            after.add(r);
            EXPECT_FALSE(after.coherent) << "axis " << k << " value " << v;
            Beam first;  // the odd ray first
            first.add(r);
            first.add(a);
            EXPECT_FALSE(first.coherent) << "axis " << k << " value " << v;
            if (v == 0.0f) {
                Beam alone;  // a single ray running inside a plane
                alone.add(r);
                EXPECT_FALSE(alone.coherent) << "axis " << k << " value " << v;
            }
        }
    // All negative is as coherent as all positive.
    Beam neg;
    neg.add(Ray{{0, 0, 0}, 0.0f, {-0.5f, -0.2f, -1.0f}, kInfinity});
    neg.add(Ray{{1, 0, 0}, 0.0f, {-0.4f, -0.3f, -1.0f}, kInfinity});
    EXPECT_TRUE(neg.coherent);
    EXPECT_EQ(neg.sign[0], -1);
    EXPECT_EQ(neg.sign[1], -1);
    EXPECT_EQ(neg.sign[2], -1);
}

TEST(MlrtaBeam, MergeBoundsBothBeams) {
    Rng rng(5);
    const int sign[3] = {1, -1, 1};
    const Float3 d = random_direction(rng, sign);
    const std::vector<Ray> ra = bundle(rng, 10, {-1, 0, 0}, 0.2f, d, 0.2f);
    const std::vector<Ray> rb = bundle(rng, 7, {1, 1, 0}, 0.3f, d, 0.2f);
    const Beam a = beam_of(ra, &kScene), b = beam_of(rb, &kScene);
    Beam m = a;
    m.merge(b);
    ASSERT_TRUE(m.coherent);
    EXPECT_EQ(m.rays, 17u);
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(m.starts.lower[k], std::min(a.starts.lower[k], b.starts.lower[k]));
        EXPECT_EQ(m.starts.upper[k], std::max(a.starts.upper[k], b.starts.upper[k]));
    }
    for (const std::vector<Ray>* rays : {&ra, &rb})
        for (const Ray& r : *rays) EXPECT_TRUE(beam_bounds_ray(m, r, rng));

    // Merging into an empty beam copies (keeping the larger padding); merging an empty one changes nothing.
    Beam e;
    e.merge(a);
    EXPECT_EQ(e.rays, a.rays);
    EXPECT_EQ(e.pad, a.pad);
    EXPECT_TRUE(e.coherent);
    Beam same = a;
    same.merge(Beam{});
    EXPECT_EQ(same.rays, a.rays);
    EXPECT_TRUE(same.coherent);

    // A beam of another sign, or an incoherent one, makes the merge incoherent.
    std::vector<Ray> flipped = rb;
    for (Ray& r : flipped) r.dir.x = -r.dir.x;
    Beam s = a;
    s.merge(beam_of(flipped, &kScene));
    EXPECT_FALSE(s.coherent);
    std::vector<Ray> flat = rb;
    flat[3].dir.z = -0.0f;
    Beam z = a;
    z.merge(beam_of(flat, &kScene));
    EXPECT_FALSE(z.coherent);
}

// `coherent` is defined by the rays' direction signs alone, so merging beams must agree with adding
// the same rays one by one, also when the rays' dominant axes differ (a camera looking along a
// diagonal: the dominant axis changes inside one tile).
TEST(MlrtaBeam, MergeIsCoherentLikeAddingTheRaysOneByOne) {
    const Ray along_x{{0, 0, 0}, 0.0f, {1.0f, 0.9f, 0.2f}, kInfinity};
    const Ray along_y{{0, 0, 0}, 0.0f, {0.9f, 1.0f, 0.2f}, kInfinity};
    Beam added;
    added.add(along_x);
    added.add(along_y);
    ASSERT_TRUE(added.coherent);
    Beam a, b;
    a.add(along_x);
    b.add(along_y);
    ASSERT_NE(a.main_axis, b.main_axis);
    Beam merged = a;
    merged.merge(b);
    EXPECT_EQ(merged.coherent, added.coherent) << "same signs on every axis, different dominant axes";
    if (merged.coherent) {
        Rng rng(6);
        EXPECT_TRUE(beam_bounds_ray(merged, along_x, rng));
        EXPECT_TRUE(beam_bounds_ray(merged, along_y, rng));
    }
}
