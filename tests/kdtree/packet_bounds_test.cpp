// Test (2) of interval traversal for a block of packets at once (PacketKernels::block_meeting, every
// instruction set the CPU has, and the scalar table's reference) against packet_misses_box, packet by
// packet: the same decisions, bit for bit, on random bounds, boxes and limits, including unbounded
// reaches and packets that start inside the box.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <vector>

#include "kdtree/packet/packet_bounds.hpp"
#include "kdtree/packet/packet_kernels.hpp"
#include "simd/isa.hpp"

using namespace beamtrace;
using namespace beamtrace::kdtree;

namespace {

Interval random_interval(std::mt19937& rng, float lo, float hi) {
    std::uniform_real_distribution<float> u(lo, hi);
    const float a = u(rng), b = u(rng);
    return {std::min(a, b), std::max(a, b)};
}

}  // namespace

TEST(BlockBounds, MeetingEqualsTheScalarTestPacketByPacket) {
    std::vector<const PacketKernels*> tables;
    for (Isa isa : {Isa::scalar, Isa::sse42, Isa::avx2, Isa::avx512}) {
        if (isa_available(isa))
            tables.push_back(&simd::select<PacketKernels>(isa));
        else
            std::printf("%s is not available on this CPU: skipped\n", isa_name(isa));
    }
    std::mt19937 rng(71);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    int met = 0, missed = 0;
    for (int round = 0; round < 4000; ++round) {
        BlockBounds block;
        block.count = 1 + round % 16;
        block.pad = round % 3 == 0 ? 0.0f : 1e-6f;
        for (int k = 0; k < 3; ++k) block.sign[k] = (round >> k) & 1 ? -1 : 1;
        PacketBounds pb[16];
        float reach[16];
        for (int p = 0; p < block.count; ++p) {
            pb[p].pad = block.pad;
            for (int k = 0; k < 3; ++k) {
                pb[p].sign[k] = block.sign[k];
                pb[p].org[k] = random_interval(rng, -2.0f, 2.0f);
                // |dir| / dir_k: at least 1 in magnitude, the sign of the axis
                const Interval m = random_interval(rng, 1.0f, round % 5 == 0 ? 1000.0f : 4.0f);
                pb[p].inv[k] = block.sign[k] > 0 ? m : Interval{-m.hi, -m.lo};
            }
            reach[p] = p % 7 == 3 ? kInfinity : unit(rng) * 10.0f;
            block.set(p, pb[p], reach[p]);
        }
        Box box;
        for (int k = 0; k < 3; ++k) {
            const Interval i = random_interval(rng, -3.0f, 3.0f);
            box.lower[k] = i.lo;
            box.upper[k] = i.hi;
        }
        const float t0 = round % 4 == 0 ? -kInfinity : unit(rng) * 4.0f - 1.0f;
        for (const PacketKernels* k : tables) {
            const std::uint32_t bits = k->block_meeting(block, box, t0);
            EXPECT_EQ(bits >> block.count, 0u) << isa_name(k->isa) << " round " << round;
            for (int p = 0; p < block.count; ++p) {
                const bool want = !packet_misses_box(pb[p], box, t0, reach[p]);
                ASSERT_EQ(((bits >> p) & 1u) != 0, want) << isa_name(k->isa) << " round " << round << " packet " << p;
                if (k == tables.front()) (want ? met : missed) += 1;
            }
        }
    }
    // Both answers are exercised.
    EXPECT_GT(met, 1000);
    EXPECT_GT(missed, 1000);
}
