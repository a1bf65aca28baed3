// The per-lane slab test of leaf boxes (kdtree/packet/lane_box_test.hpp): the SIMD kernels return exactly the scalar
// reference's lanes, and no ray whose segment meets the box (exact double-precision test) is dropped.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>

#include <vector>

#include "hand_tree.hpp"
#include "kdtree/packet/packet_kernels.hpp"

using namespace beamtrace;
using namespace beamtrace::mlrta;
using namespace beamtrace::kdtree;
using namespace beamtrace::mlrta::test;

namespace {

std::vector<Isa> isas() {
    std::vector<Isa> out;
    for (Isa isa : {Isa::scalar, Isa::sse42, Isa::avx2, Isa::avx512})
        if (isa_available(isa)) out.push_back(isa);
    return out;
}

struct Case {
    Packet16 packet;
    Box box;
};

// 16 rays with scattered origins and directions (no zero component), some segments bounded, some
// flat boxes, boxes near the rays and far from them; inactive lanes hold garbage.
Case random_case(Rng& rng) {
    Case c;
    const float scale = rng() % 3 == 0 ? 1000.0f : 2.0f;
    for (int i = 0; i < 16; ++i) {
        Ray r;
        r.org = Float3{uniform(rng, -scale, scale), uniform(rng, -scale, scale), uniform(rng, -scale, scale)};
        for (int k = 0; k < 3; ++k) {
            float d = uniform(rng, -1, 1);
            if (std::fabs(d) < 1e-3f) d = rng() % 2 ? 1e-3f : -1e-3f;
            r.dir[k] = rng() % 50 == 0 ? d * 1e-30f : d;
        }
        r.tnear = rng() % 2 ? 0.0f : uniform(rng, 0, scale);
        r.tfar = rng() % 2 ? kInfinity : r.tnear + uniform(rng, 0, 4 * scale);
        c.packet.set_ray(i, r);
    }
    const Ray aim = c.packet.ray(int(rng() % 16));
    c.packet.active = std::uint32_t(rng() & 0xFFFFu);
    for (int i = 0; i < 16; ++i)
        if (!((c.packet.active >> i) & 1u)) c.packet.org_x[i] = NAN;
    const Float3 centre =
        rng() % 2 ? Float3{uniform(rng, -scale, scale), uniform(rng, -scale, scale), uniform(rng, -scale, scale)}
                  : aim.org + aim.dir * uniform(rng, 0, 3 * scale);
    for (int k = 0; k < 3; ++k) {
        const float half = rng() % 4 == 0 ? 0.0f : uniform(rng, 0, scale * 0.3f);
        c.box.lower[k] = centre[k] - half;
        c.box.upper[k] = centre[k] + half;
    }
    return c;
}

}  // namespace

TEST(MlrtaLaneSlabs, SetUpIsEachLanesCopyAndReciprocal) {
    // make_lane_box_rays (SSE) against the lane-by-lane definition, bit for bit, zero and
    // non-finite components included.
    Rng rng(92);
    for (int n = 0; n < 2000; ++n) {
        Case c = random_case(rng);
        float* dir[3] = {c.packet.dir_x, c.packet.dir_y, c.packet.dir_z};
        if (n % 3 == 0) dir[n % 9 / 3][n % 16] = n % 2 ? 0.0f : -0.0f;
        if (n % 7 == 0) dir[0][(n / 7) % 16] = n % 2 ? kInfinity : std::nanf("");
        const LaneBoxRays s = make_lane_box_rays(c.packet, 1e-6f);
        const float* org[3] = {c.packet.org_x, c.packet.org_y, c.packet.org_z};
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 16; ++i) {
                const float inv = 1.0f / dir[k][i];
                ASSERT_EQ(std::bit_cast<std::uint32_t>(s.inv[k][i]), std::bit_cast<std::uint32_t>(inv)) << n;
                ASSERT_EQ(std::bit_cast<std::uint32_t>(s.org[k][i]), std::bit_cast<std::uint32_t>(org[k][i])) << n;
            }
        for (int i = 0; i < 16; ++i) ASSERT_EQ(s.tnear[i], c.packet.tnear[i]) << n;
        ASSERT_EQ(s.pad, 1e-6f);
    }
}

TEST(MlrtaLaneSlabs, KernelsEqualTheReferenceAndDropNoRayThatMeetsTheBox) {
    Rng rng(91);
    std::vector<Case> cases;
    for (int n = 0; n < 30000; ++n) cases.push_back(random_case(rng));
    for (Isa isa : isas()) {
        const LaneBoxKernel kernel = beamtrace::simd::select<PacketKernels>(isa).lane_box;
        std::uint64_t met = 0, dropped = 0;
        for (std::size_t n = 0; n < cases.size(); ++n) {
            const Case& c = cases[n];
            const LaneBoxRays s = make_lane_box_rays(c.packet, 1e-6f);
            const std::uint32_t bits = kernel(s, c.packet.tfar, c.packet.active, c.box);
            ASSERT_EQ(bits, lanes_meeting_box(s, c.packet.tfar, c.packet.active, c.box))
                << isa_name(isa) << " case " << n;
            ASSERT_EQ(bits & ~c.packet.active, 0u);
            for (std::uint32_t b = c.packet.active; b; b &= b - 1) {
                const int i = __builtin_ctz(b);
                const bool exact = segment_meets_box(c.packet.ray(i), c.box);
                ASSERT_TRUE(!exact || ((bits >> i) & 1u)) << isa_name(isa) << " case " << n << " lane " << i;
                met += exact;
                dropped += !((bits >> i) & 1u);
            }
        }
        EXPECT_GT(met, 5000u) << isa_name(isa);
        EXPECT_GT(dropped, 10000u) << isa_name(isa) << ": most rays miss a random box";
    }
}
