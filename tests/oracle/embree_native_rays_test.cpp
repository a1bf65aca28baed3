// Rays prebuilt in Embree's layouts (the anchor engines): every layout and both context flags give the
// oracle's answers, rays Embree cannot take (and inactive lanes) report nothing, reset() makes a
// second trace give the same answers, and traces split over units run concurrently.
#include "oracle/embree_native_rays.hpp"
#include "oracle/embree_segment.hpp"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "beamtrace/error.hpp"
#include "hand_scenes.hpp"

namespace beamtrace::oracle {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr EmbreeLayout kLayouts[] = {EmbreeLayout::single, EmbreeLayout::packet16, EmbreeLayout::stream};
constexpr EmbreeContextFlag kFlags[] = {EmbreeContextFlag::coherent, EmbreeContextFlag::incoherent};

// Packets of rays at the cube from all around, with random active masks (one packet all inactive),
// and among them rays the oracle's rules turn away or move: NaN, zero direction, reversed segments,
// negative tnear, directions beyond Embree's range.
std::vector<Packet16> test_packets(std::size_t count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Packet16> packets(count);
    for (std::size_t p = 0; p < count; ++p) {
        for (int i = 0; i < 16; ++i) {
            const Float3 org{4 * u(rng), 4 * u(rng), 4 * u(rng)};
            const Float3 target{1.3f * u(rng), 1.3f * u(rng), 1.3f * u(rng)};
            Ray r{org, 0.0f, target - org, (i % 5 == 0) ? 0.5f + 2.0f * (u(rng) + 1.0f) : kInfinity};
            switch ((p * 16 + std::size_t(i)) % 23) {
                case 3:
                    r.org.x = kNaN;
                    break;
                case 7:
                    r.dir = {0, 0, 0};
                    break;
                case 11:
                    r.tnear = 2.0f, r.tfar = 1.0f;
                    break;
                case 13:
                    r.tnear = -3.0f;
                    break;
                case 17:
                    r.dir = r.dir * 1e20f;
                    break;
                default:
                    break;
            }
            packets[p].set_ray(i, r);
        }
        packets[p].active = p == 1 ? 0u : (p == 0 ? 0xFFFFu : std::uint32_t(rng() & 0xFFFFu));
    }
    return packets;
}

class EmbreeNativeRaysTest : public ::testing::Test {
protected:
    EmbreeOracle oracle{test::cube()};
    std::vector<Packet16> packets = test_packets(80, 5);
};

TEST_F(EmbreeNativeRaysTest, ClosestHitsOfEveryLayoutAndFlagAreTheOraclesAfterEveryReset) {
    int hits_seen = 0;
    for (EmbreeLayout layout : kLayouts) {
        EmbreeNativeRays native(oracle, layout, packets, true);
        for (EmbreeContextFlag flag : kFlags)
            for (int pass = 0; pass < 2; ++pass) {  // the second pass starts from reset()
                SCOPED_TRACE(std::string("layout ") + std::to_string(int(layout)) + ", " + to_string(flag) + ", pass " +
                             std::to_string(pass));
                native.reset();
                native.trace(flag, 0, native.units());
                std::vector<Hit> hits;
                native.hits(hits);
                ASSERT_EQ(hits.size(), packets.size() * 16);
                for (std::size_t slot = 0; slot < hits.size(); ++slot) {
                    const Packet16& p = packets[slot / 16];
                    const int lane = int(slot % 16);
                    if (!((p.active >> lane) & 1u)) {
                        ASSERT_FALSE(hits[slot].hit()) << slot;
                        continue;
                    }
                    const Hit reference = oracle.intersect1(p.ray(lane));
                    ASSERT_EQ(hits[slot].triangle, reference.triangle) << slot;
                    if (!reference.hit()) continue;
                    ++hits_seen;
                    EXPECT_NEAR(hits[slot].t, reference.t, 1e-6f * std::max(1.0f, std::fabs(reference.t))) << slot;
                    EXPECT_NEAR(hits[slot].u, reference.u, 1e-6f) << slot;
                    EXPECT_NEAR(hits[slot].v, reference.v, 1e-6f) << slot;
                }
            }
    }
    EXPECT_GT(hits_seen, 1000);
}

TEST_F(EmbreeNativeRaysTest, OcclusionOfEveryLayoutAndFlagIsTheOraclesAfterEveryReset) {
    int blocked_seen = 0;
    for (EmbreeLayout layout : kLayouts) {
        EmbreeNativeRays native(oracle, layout, packets, false);
        for (EmbreeContextFlag flag : kFlags)
            for (int pass = 0; pass < 2; ++pass) {
                SCOPED_TRACE(std::string("layout ") + std::to_string(int(layout)) + ", " + to_string(flag));
                native.reset();
                native.trace(flag, 0, native.units());
                std::vector<std::uint8_t> occluded;
                native.occluded(occluded);
                ASSERT_EQ(occluded.size(), packets.size() * 16);
                for (std::size_t slot = 0; slot < occluded.size(); ++slot) {
                    const Packet16& p = packets[slot / 16];
                    const int lane = int(slot % 16);
                    const bool active = (p.active >> lane) & 1u;
                    ASSERT_EQ(occluded[slot] != 0, active && oracle.occluded1(p.ray(lane))) << slot;
                    blocked_seen += occluded[slot];
                }
            }
    }
    EXPECT_GT(blocked_seen, 1000);
}

TEST_F(EmbreeNativeRaysTest, RaysEmbreeCannotTakeAreLeftOutOfTheLayout) {
    std::size_t active = 0, takeable = 0;
    for (const Packet16& p : packets)
        for (int i = 0; i < 16; ++i)
            if ((p.active >> i) & 1u) {
                ++active;
                takeable += to_embree(p.ray(i)).has_value();
            }
    ASSERT_LT(takeable, active);  // the set holds rays the rules turn away
    for (EmbreeLayout layout : kLayouts) {
        const EmbreeNativeRays native(oracle, layout, packets, true);
        EXPECT_EQ(native.rays(), takeable);
        EXPECT_GT(native.bytes(), takeable * sizeof(float) * 8);
    }
    // Packets with no ray to trace are not handed to Embree at all.
    EXPECT_EQ(EmbreeNativeRays(oracle, EmbreeLayout::packet16, packets, true).units(), packets.size() - 1);
}

TEST_F(EmbreeNativeRaysTest, UnitsTracedConcurrentlyGiveTheSameAnswers) {
    const std::vector<Packet16> many = test_packets(2000, 9);
    for (EmbreeLayout layout : kLayouts) {
        EmbreeNativeRays one(oracle, layout, many, true), split(oracle, layout, many, true);
        one.trace(EmbreeContextFlag::coherent, 0, one.units());
        tbb::parallel_for(std::size_t{0}, split.units(),
                          [&](std::size_t k) { split.trace(EmbreeContextFlag::coherent, k, k + 1); });
        std::vector<Hit> a, b;
        one.hits(a);
        split.hits(b);
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t slot = 0; slot < a.size(); ++slot) {
            ASSERT_EQ(a[slot].triangle, b[slot].triangle) << slot;
            ASSERT_EQ(a[slot].t, b[slot].t) << slot;
        }
    }
}

TEST_F(EmbreeNativeRaysTest, AskingForTheOtherQueryKindIsAnError) {
    const EmbreeNativeRays closest(oracle, EmbreeLayout::packet16, packets, true);
    const EmbreeNativeRays occlusion(oracle, EmbreeLayout::stream, packets, false);
    std::vector<Hit> hits;
    std::vector<std::uint8_t> occluded;
    EXPECT_THROW(closest.occluded(occluded), Error);
    EXPECT_THROW(occlusion.hits(hits), Error);
}

TEST(EmbreeNativeRays, NonRobustSceneSaysSoAndStillHits) {
    const EmbreeOracle fast(test::cube(), EmbreeSceneOptions{false});
    EXPECT_FALSE(fast.robust());
    EXPECT_TRUE(EmbreeOracle(test::cube()).robust());
    std::vector<Packet16> packets(1);
    for (int i = 0; i < 16; ++i)
        packets[0].set_ray(i, Ray{{0.1f * float(i % 4) - 0.2f, 0.05f, -5.0f}, 0.0f, {0, 0, 1}, kInfinity});
    packets[0].active = 0xFFFFu;
    EmbreeNativeRays native(fast, EmbreeLayout::packet16, packets, true);
    native.trace(EmbreeContextFlag::coherent, 0, native.units());
    std::vector<Hit> hits;
    native.hits(hits);
    for (int i = 0; i < 16; ++i) {
        ASSERT_TRUE(hits[std::size_t(i)].hit()) << i;
        EXPECT_NEAR(hits[std::size_t(i)].t, 4.0f, 1e-5f) << i;
        EXPECT_EQ(hits[std::size_t(i)].triangle / 2, 4u) << i;  // the -z face
    }
}

}  // namespace
}  // namespace beamtrace::oracle
