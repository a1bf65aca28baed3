// The packet form of the ray contract (segment_lanes, SSE) agrees lane by lane with the single-ray
// form (describes_segment) on rays made of every kind of odd value.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <random>

#include "common/ray_validity.hpp"

using namespace beamtrace;

TEST(RayValidity, PacketLanesAgreeWithSingleRays) {
    const float odd[] = {0.0f,     -0.0f,     1.0f,       -2.5f, 1e-40f, FLT_MAX,
                         -FLT_MAX, kInfinity, -kInfinity, NAN,   3e38f,  1e-30f};
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> pick(0, int(std::size(odd)) - 1), coin(0, 3);
    int valid = 0, invalid = 0;
    for (int iter = 0; iter < 20000; ++iter) {
        Packet16 p;
        for (int i = 0; i < 16; ++i) {
            float* fields[8] = {&p.org_x[i], &p.org_y[i], &p.org_z[i], &p.dir_x[i],
                                &p.dir_y[i], &p.dir_z[i], &p.tnear[i], &p.tfar[i]};
            for (float* f : fields) *f = coin(rng) ? float(int(rng() % 200) - 100) * 0.1f : odd[pick(rng)];
        }
        p.active = std::uint32_t(rng() & 0xFFFFu);
        const std::uint32_t lanes = segment_lanes(p);
        ASSERT_EQ(lanes >> 16, 0u);
        for (int i = 0; i < 16; ++i) {
            const bool expected = describes_segment(p.ray(i));
            ASSERT_EQ(((lanes >> i) & 1u) != 0, expected) << "iteration " << iter << " lane " << i;
            (expected ? valid : invalid)++;
        }
    }
    EXPECT_GT(valid, 10000);
    EXPECT_GT(invalid, 10000);
}
