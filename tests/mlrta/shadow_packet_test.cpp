// Shadow packets traced from their light (reverse_towards_light): the rays of a packet aimed at one
// light become the same segments from exactly that point; anything else is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "beamtrace/mlrta.hpp"
#include "mlrta/shadow_reversal.hpp"
#include "hand_tree.hpp"

using namespace beamtrace;
using beamtrace::mlrta::reverse_towards_light;
using namespace beamtrace::mlrta::test;

namespace {

double distance(Float3 a, const double b[3]) {
    const double dx = a.x - b[0], dy = a.y - b[1], dz = a.z - b[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// Shadow rays as the workload makes them: from surface points towards the light, direction
// light - origin, [tnear, tfar] inside [0, 1).
Packet16 shadow_packet(Rng& rng, Float3 light, float scale, std::uint32_t active) {
    Packet16 p;
    for (int i = 0; i < 16; ++i) {
        Ray r;
        r.org = Float3{uniform(rng, -scale, scale), uniform(rng, -scale, scale), uniform(rng, -scale, scale)};
        r.dir = light - r.org;
        r.tnear = rng() % 2 ? 0.0f : uniform(rng, 0.0f, 1e-3f);
        r.tfar = 1.0f - (rng() % 2 ? 1e-4f : uniform(rng, 1e-4f, 0.5f));
        p.set_ray(i, r);
    }
    p.active = active;
    return p;
}

}  // namespace

TEST(MlrtaShadowPacket, SameSegmentsFromExactlyTheLight) {
    Rng rng(101);
    int reversed = 0;
    for (int iter = 0; iter < 3000; ++iter) {
        const float scale = iter % 2 ? 10.0f : 1.0f;
        const Float3 light{uniform(rng, -scale, scale), uniform(rng, -scale, scale), uniform(rng, -scale, scale)};
        const std::uint32_t active = iter % 5 ? 0xFFFFu : (std::uint32_t(rng()) & 0xFFFFu) | 1u;
        const Packet16 p = shadow_packet(rng, light, scale, active);
        const float tolerance = 1e-6f * scale * 3.5f;
        Packet16 out = p;
        out.org_x[0] = 12345.0f;  // overwritten only on success
        if (!reverse_towards_light(p, tolerance, out)) {
            EXPECT_EQ(out.org_x[0], 12345.0f) << "a refused packet is left alone";
            continue;
        }
        ++reversed;
        ASSERT_EQ(out.active, p.active);
        const int lead = __builtin_ctz(active);
        for (int i = 0; i < 16; ++i) {
            const Ray a = p.ray(i), b = out.ray(i);
            if (!((active >> i) & 1u)) {
                ASSERT_EQ(std::memcmp(&a, &b, sizeof(Ray)), 0) << "inactive lanes are copied";
                continue;
            }
            ASSERT_EQ(b.org, out.ray(lead).org) << "one origin, bit for bit";
            // The ends, in double: the original start and far end against the new far end and start.
            double start[3], end[3];
            for (int k = 0; k < 3; ++k) {
                start[k] = double(a.org[k]) + double(a.dir[k]) * a.tnear;
                end[k] = double(a.org[k]) + double(a.dir[k]) * a.tfar;
            }
            const Float3 new_end = b.org + b.dir * b.tfar, new_start = b.org + b.dir * b.tnear;
            EXPECT_LE(distance(new_end, start), 4.0 * tolerance) << "iteration " << iter << " lane " << i;
            EXPECT_LE(distance(new_start, end), 4.0 * tolerance) << "iteration " << iter << " lane " << i;
            EXPECT_LE(b.tnear, b.tfar);
        }
    }
    EXPECT_GT(reversed, 2500);
}

TEST(MlrtaShadowPacket, RefusesRaysAimedElsewhereAndCoarseCoordinates) {
    Rng rng(102);
    for (int iter = 0; iter < 500; ++iter) {
        const Float3 light{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
        Packet16 p = shadow_packet(rng, light, 1.0f, 0xFFFFu);
        Packet16 out;
        ASSERT_TRUE(reverse_towards_light(p, 1e-5f, out));
        Packet16 other = p;
        other.dir_y[int(rng() % 16)] += 0.01f;  // one ray aims beside the light
        EXPECT_FALSE(reverse_towards_light(other, 1e-5f, out));
        Packet16 beyond = p;
        beyond.tfar[int(rng() % 16)] = 1.5f;  // past the light
        EXPECT_FALSE(reverse_towards_light(beyond, 1e-5f, out));
        // The same scene 1e5 from the world origin: floats are 1/128 apart there, far coarser
        // than the tolerance.
        const Float3 far_light = light + Float3{1e5f, 1e5f, 1e5f};
        Packet16 coarse = shadow_packet(rng, far_light, 1.0f, 0xFFFFu);
        for (int i = 0; i < 16; ++i) {
            coarse.org_x[i] += 1e5f, coarse.org_y[i] += 1e5f, coarse.org_z[i] += 1e5f;
            coarse.dir_x[i] = far_light.x - coarse.org_x[i];
            coarse.dir_y[i] = far_light.y - coarse.org_y[i];
            coarse.dir_z[i] = far_light.z - coarse.org_z[i];
        }
        EXPECT_FALSE(reverse_towards_light(coarse, 1e-5f, out));
    }
    Packet16 none;
    none.active = 0;
    Packet16 out;
    EXPECT_FALSE(reverse_towards_light(none, 1.0f, out));
}
