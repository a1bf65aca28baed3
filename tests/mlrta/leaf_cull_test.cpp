// The leaf test (2) of section 3.3 (Figure 4): a beam passing beside a box, projected on the plane of
// two axes, is separated from it when the slab entries of one axis all come after the slab exits of
// the other. The 8 cases of the figure (direction signs along the two axes, beam on either side of the
// box) for each of the three pairs of axes; segments that end before the box or start after it; and
// conservativeness. The same for the direct 4-plane test (Assarsson and Moller) on one-origin beams.
#include <gtest/gtest.h>

#include <cmath>

#include "hand_tree.hpp"
#include "mlrta/direct_frustum_cull.hpp"
#include "mlrta/inverse_frustum_cull.hpp"

using namespace beamtrace;
using namespace beamtrace::mlrta;
using namespace beamtrace::mlrta::test;

namespace {

const Box kBox{{0, 0, 0}, {1, 1, 1}};
const Box kScene{{-4, -4, -4}, {4, 4, 4}};

// Rays moving diagonally in the plane of axes a and b (signs sa, sb) past the box's corner on one side
// (`side` 0 or 1), 0.2 units off the supporting line through that corner; along the third axis c they
// stay inside the box's slab. `spread_org` 0 gives one origin.
std::vector<Ray> past_corner(Rng& rng, int a, int b, int sa, int sb, int side, float spread_org) {
    const int c = 3 - a - b;
    // The unit normal of the direction in the (a, b) plane, and the box corner farthest along +-n.
    const double na = -double(sb), nb = double(sa), len = std::sqrt(2.0);
    const double s = side ? 1.0 : -1.0;
    Float3 p;
    p[a] = (s * na > 0) ? 1.0f : 0.0f;
    p[b] = (s * nb > 0) ? 1.0f : 0.0f;
    p[a] += float(s * na / len * 0.2);
    p[b] += float(s * nb / len * 0.2);
    p[c] = 0.5f;
    Float3 d;
    d[a] = float(sa) * 1.02f;  // axis a dominant: the beam's main axis
    d[b] = float(sb);
    d[c] = 0.02f;
    const Float3 org = p - d * 2.0f;
    return bundle(rng, 16, org, spread_org, d, 0.02f);
}

bool any_meets(const std::vector<Ray>& rays, const Box& box) {
    for (const Ray& r : rays)
        if (segment_meets_box(r, box)) return true;
    return false;
}

}  // namespace

TEST(MlrtaLeafCull, Figure4EightCasesPerPairOfAxesAreMissed) {
    Rng rng(21);
    const int pairs[3][2] = {{0, 1}, {1, 2}, {0, 2}};
    int cases = 0;
    for (const auto& pair : pairs)
        for (int sa : {1, -1})
            for (int sb : {1, -1})
                for (int side : {0, 1})
                    for (int order = 0; order < 2; ++order) {  // either axis of the pair dominant
                        const int a = pair[order], b = pair[1 - order];
                        const std::vector<Ray> rays = past_corner(rng, a, b, sa, sb, side, 0.02f);
                        ASSERT_FALSE(any_meets(rays, kBox)) << "the hand-made rays pass beside the box";
                        for (const Beam& beam : {beam_of(rays, &kScene), packet_beam_of(rays, &kScene)}) {
                            ASSERT_TRUE(beam.coherent);
                            EXPECT_TRUE(beam_misses_box(beam, kBox))
                                << "axes " << a << "," << b << " signs " << sa << "," << sb << " side " << side;
                        }
                        // Moved across the box, the same rays do meet it: never reported missed.
                        std::vector<Ray> through = rays;
                        for (Ray& r : through)
                            for (int k = 0; k < 3; ++k) r.org[k] += 0.5f - (rays[0].org[k] + rays[0].dir[k] * 2.0f);
                        ASSERT_TRUE(any_meets(through, kBox));
                        EXPECT_FALSE(beam_misses_box(beam_of(through, &kScene), kBox));
                        ++cases;
                    }
    EXPECT_EQ(cases, 48);
}

TEST(MlrtaLeafCull, SegmentsEndingBeforeOrStartingAfterTheBoxAreMissed) {
    Rng rng(22);
    // Along +x through the box's middle: the box lies between x = 0 and 1, the starts at x = -2.
    std::vector<Ray> rays = bundle(rng, 16, {-2.0f, 0.5f, 0.5f}, 0.05f, {1.0f, 0.05f, 0.04f}, 0.2f);
    EXPECT_FALSE(beam_misses_box(beam_of(rays, &kScene), kBox));
    std::vector<Ray> short_rays = rays;
    for (Ray& r : short_rays) r.tfar = 1.5f;  // every segment ends before x = 0
    ASSERT_FALSE(any_meets(short_rays, kBox));
    EXPECT_TRUE(beam_misses_box(beam_of(short_rays, &kScene), kBox));
    std::vector<Ray> late = rays;
    for (Ray& r : late) r.tnear = 4.0f;  // every segment starts after x = 1
    ASSERT_FALSE(any_meets(late, kBox));
    EXPECT_TRUE(beam_misses_box(beam_of(late, &kScene), kBox));
    // One ray long enough keeps the box.
    short_rays[5].tfar = 3.0f;
    ASSERT_TRUE(any_meets(short_rays, kBox));
    EXPECT_FALSE(beam_misses_box(beam_of(short_rays, &kScene), kBox));
    // Pointing away: every slab exit lies behind the starts.
    for (Ray& r : rays) r.dir = r.dir * -1.0f;
    EXPECT_TRUE(beam_misses_box(beam_of(rays, &kScene), kBox));
}

// Random boxes (flat ones included) and coherent beams: a box some ray's segment meets is never
// reported missed; most boxes no ray meets are.
TEST(MlrtaLeafCull, ConservativeForRandomBeamsAndBoxes) {
    Rng rng(23);
    int met = 0, missed_truly = 0, missed_reported = 0;
    for (int trial = 0; trial < 40000; ++trial) {
        Box box;
        box.extend(Float3{uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2)});
        box.extend(box.lower + Float3{uniform(rng, 0, 1.5f), uniform(rng, 0, 1.5f), uniform(rng, 0, 1.5f)});
        if (rng() % 5 == 0) {  // a flat box, as flat leaves are
            const int k = int(rng() % 3);
            box.upper[k] = box.lower[k];
        }
        Float3 dir;
        for (int a = 0; a < 3; ++a) dir[a] = (rng() % 2 ? 1.0f : -1.0f) * uniform(rng, 0.02f, 1.0f);
        if (rng() % 8 == 0) {  // nearly parallel to a slab's planes, down to denormals
            const float tiny[] = {1e-8f, 1e-20f, 1e-38f, 1e-41f, 1e-45f};
            const int a = int(rng() % 3);
            dir[a] = (dir[a] > 0 ? 1.0f : -1.0f) * tiny[rng() % 5];
        }
        std::vector<Ray> rays =
            bundle(rng, 1 + int(rng() % 16), {uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3)},
                   rng() % 3 ? uniform(rng, 0.0f, 0.3f) : 0.0f, dir, uniform(rng, 0.0f, 0.3f));
        for (Ray& r : rays) {
            if (rng() % 4 == 0) r.tnear = uniform(rng, 0.0f, 2.0f);
            if (rng() % 3 == 0) r.tfar = r.tnear + uniform(rng, 0.0f, 4.0f);
        }
        if (rng() % 3 == 0) {  // one ray grazing a corner or an edge of the box
            Float3 target;
            for (int a = 0; a < 3; ++a)
                target[a] =
                    rng() % 3 ? (rng() % 2 ? box.lower[a] : box.upper[a]) : uniform(rng, box.lower[a], box.upper[a]);
            rays[0].org = target - rays[0].dir * uniform(rng, -1.0f, 3.0f);
            rays[0].tnear = 0.0f;
            rays[0].tfar = kInfinity;
        }
        const Beam beam = trial % 2 ? beam_of(rays, &kScene) : packet_beam_of(rays, &kScene);
        ASSERT_TRUE(beam.coherent);
        const bool meets = any_meets(rays, box);
        const bool missed = beam_misses_box(beam, box);
        if (meets) {
            ++met;
            ASSERT_FALSE(missed) << "trial " << trial << ": a ray meets the box";
        } else {
            ++missed_truly;
            missed_reported += missed;
        }
    }
    EXPECT_GT(met, 2000);
    EXPECT_GT(missed_reported, missed_truly / 2);
}

TEST(MlrtaDirectCull, FrustumOnlyForCoherentBeamsWithOneOrigin) {
    Rng rng(24);
    const std::vector<Ray> one = bundle(rng, 16, {0, 0, 0}, 0.0f, {1.0f, 0.3f, -0.2f}, 0.1f);
    EXPECT_TRUE(make_frustum(beam_of(one, &kScene)).valid);
    EXPECT_TRUE(
        make_frustum(pinhole_beam({1, 2, 3}, {0.5f, -1.0f, 0.2f}, {0.01f, 0, 0}, {0, 0, 0.01f}, 0, 0, 7, 7)).valid);
    const std::vector<Ray> many = bundle(rng, 16, {0, 0, 0}, 0.1f, {1.0f, 0.3f, -0.2f}, 0.1f);
    EXPECT_FALSE(make_frustum(beam_of(many, &kScene)).valid);
    std::vector<Ray> mixed = one;
    mixed[3].dir.y = -mixed[3].dir.y;
    EXPECT_FALSE(make_frustum(beam_of(mixed, &kScene)).valid);
}

TEST(MlrtaDirectCull, Figure4EightCasesPerPairOfAxesAreMissed) {
    Rng rng(25);
    const int pairs[3][2] = {{0, 1}, {1, 2}, {0, 2}};
    int cases = 0;
    for (const auto& pair : pairs)
        for (int sa : {1, -1})
            for (int sb : {1, -1})
                for (int side : {0, 1})
                    for (int order = 0; order < 2; ++order) {
                        const int a = pair[order], b = pair[1 - order];
                        const std::vector<Ray> rays = past_corner(rng, a, b, sa, sb, side, 0.0f);
                        ASSERT_FALSE(any_meets(rays, kBox));
                        const Frustum4 f = make_frustum(beam_of(rays, &kScene));
                        ASSERT_TRUE(f.valid);
                        EXPECT_TRUE(frustum_misses_box(f, kBox))
                            << "axes " << a << "," << b << " signs " << sa << "," << sb << " side " << side;
                        ++cases;
                    }
    EXPECT_EQ(cases, 48);
}

// Random one-origin beams (half-lines: the direct test knows no segment ends) and random boxes.
TEST(MlrtaDirectCull, ConservativeForRandomBeamsAndBoxes) {
    Rng rng(26);
    int met = 0, missed_truly = 0, missed_reported = 0;
    for (int trial = 0; trial < 40000; ++trial) {
        Box box;
        box.extend(Float3{uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2)});
        box.extend(box.lower + Float3{uniform(rng, 0, 1.5f), uniform(rng, 0, 1.5f), uniform(rng, 0, 1.5f)});
        if (rng() % 5 == 0) {
            const int k = int(rng() % 3);
            box.upper[k] = box.lower[k];
        }
        Float3 dir;
        for (int a = 0; a < 3; ++a) dir[a] = (rng() % 2 ? 1.0f : -1.0f) * uniform(rng, 0.02f, 1.0f);
        std::vector<Ray> rays =
            bundle(rng, 2 + int(rng() % 15), {uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3)}, 0.0f, dir,
                   uniform(rng, 0.0f, 0.3f));
        if (rng() % 3 == 0) {  // one ray aimed at a corner or an edge of the box
            Float3 target;
            for (int a = 0; a < 3; ++a)
                target[a] =
                    rng() % 3 ? (rng() % 2 ? box.lower[a] : box.upper[a]) : uniform(rng, box.lower[a], box.upper[a]);
            const Float3 d = target - rays[0].org;
            bool same_signs = true;
            for (int a = 0; a < 3; ++a) same_signs = same_signs && d[a] != 0.0f && (d[a] > 0) == (dir[a] > 0);
            if (same_signs) rays[0].dir = d;
        }
        const Beam beam = trial % 2 ? beam_of(rays, &kScene) : packet_beam_of(rays, &kScene);
        ASSERT_TRUE(beam.coherent);
        const Frustum4 f = make_frustum(beam);
        ASSERT_TRUE(f.valid);
        const bool meets = any_meets(rays, box);
        const bool missed = frustum_misses_box(f, box);
        if (meets) {
            ++met;
            ASSERT_FALSE(missed) << "trial " << trial << ": a ray meets the box";
        } else {
            ++missed_truly;
            missed_reported += missed;
        }
    }
    EXPECT_GT(met, 1500);
    EXPECT_GT(missed_reported, missed_truly / 2);
}
