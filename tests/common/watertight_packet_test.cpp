// The SSE set-up of a packet's watertight rays (make_watertight_packet) is the reference's
// (make_watertight_ray per lane), bit for bit, for every kind of direction: dominant axes of either
// sign, ties between components, zeros of either sign, tiny and huge values, NaN and infinities,
// inactive lanes with garbage.
#include <gtest/gtest.h>

#include <bit>
#include <cfloat>
#include <cmath>
#include <random>

#include "common/watertight_ray.hpp"

using namespace beamtrace;

namespace {

bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

}  // namespace

TEST(WatertightPacket, SseSetUpEqualsTheReferenceBitForBit) {
    const float odd[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, -0.5f, 1e-30f, -1e-40f, 3e38f, -FLT_MAX, kInfinity, NAN};
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-2, 2);
    for (int iter = 0; iter < 20000; ++iter) {
        Packet16 p;
        for (int i = 0; i < 16; ++i) {
            float* f[8] = {&p.org_x[i], &p.org_y[i], &p.org_z[i], &p.dir_x[i],
                           &p.dir_y[i], &p.dir_z[i], &p.tnear[i], &p.tfar[i]};
            for (float* v : f) *v = rng() % 5 ? u(rng) : odd[rng() % std::size(odd)];
            if (rng() % 7 == 0) p.dir_y[i] = p.dir_x[i];  // ties
            if (rng() % 7 == 0) p.dir_z[i] = -p.dir_x[i];
        }
        p.active = iter % 3 ? std::uint32_t(rng() & 0xFFFFu) : 0xFFFFu;
        if (iter % 11 == 0)
            for (int i = 1; i < 16; ++i) {  // one origin and one axis order for all: the shared paths
                p.org_x[i] = p.org_x[0], p.org_y[i] = p.org_y[0], p.org_z[i] = p.org_z[0];
                p.dir_x[i] = std::fabs(p.dir_x[0]) + 1.0f, p.dir_y[i] = 0.5f, p.dir_z[i] = 0.25f;
            }
        const WatertightPacket16 a = make_watertight_packet(p), b = make_watertight_packet_reference(p);
        for (int i = 0; i < 16; ++i) {
            const float* fa[11] = {a.org_x, a.org_y, a.org_z, a.kx, a.ky, a.kz, a.sx, a.sy, a.sz, a.tnear, a.tfar};
            const float* fb[11] = {b.org_x, b.org_y, b.org_z, b.kx, b.ky, b.kz, b.sx, b.sy, b.sz, b.tnear, b.tfar};
            for (int k = 0; k < 11; ++k)
                ASSERT_TRUE(same_bits(fa[k][i], fb[k][i])) << "iteration " << iter << " lane " << i << " field " << k;
        }
        ASSERT_EQ(a.active, b.active);
        ASSERT_EQ(a.same_axes, b.same_axes);
        ASSERT_EQ(a.same_origin, b.same_origin);
        ASSERT_EQ(a.first, b.first);
        for (int k = 0; k < 3; ++k) ASSERT_EQ(a.axis[k], b.axis[k]);
    }
}
