// The per-packet set-up of interval traversal (packet_lanes.hpp: SSE, four lanes per instruction)
// against its lane-by-lane definition, bit for bit: direction lengths, unit directions and lane
// classes; ranges over some lanes; the farthest distance; each lane's cut to a cell and the ranges
// of the cut packet. Random packets with inactive lanes, zero and tiny components, negative and
// mixed signs, and cells that some lanes miss.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <random>

#include "common/ray_validity.hpp"
#include "kdtree/packet/packet_lanes.hpp"

using namespace beamtrace;
using namespace beamtrace::kdtree;

namespace {

std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }

Packet16 random_packet(std::mt19937& rng, int round) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    Packet16 p;
    const float spread = round % 3 == 0 ? 1.0f : 0.05f;  // coherent or not
    const float base[3] = {u(rng), u(rng), u(rng)};
    for (int i = 0; i < 16; ++i) {
        p.org_x[i] = u(rng) * 2.0f;
        p.org_y[i] = u(rng) * 2.0f;
        p.org_z[i] = round % 2 ? p.org_z[0] : u(rng) * 2.0f;
        p.dir_x[i] = base[0] + spread * u(rng);
        p.dir_y[i] = base[1] + spread * u(rng);
        p.dir_z[i] = (base[2] + spread * u(rng)) * (round % 5 == 0 ? 1e6f : 1.0f);
        p.tnear[i] = std::max(0.0f, u(rng));
        p.tfar[i] = i % 5 == 0 ? kInfinity : p.tnear[i] + 3.0f * (u(rng) + 1.0f);
    }
    if (round % 4 == 1) p.dir_x[round % 16] = round % 8 == 1 ? 0.0f : -0.0f;  // a zero component
    if (round % 4 == 2) p.dir_y[round % 16] = 1e-39f;                        // denormal: flat
    if (round % 7 == 3) p.tfar[(round + 3) % 16] = -1.0f;                      // no segment
    p.active = round % 6 == 0 ? 0xFFFFu : (std::uint32_t(rng()) & 0xFFFFu) | 1u;
    return p;
}

// std::min / std::max folds over the lanes, in lane order.
Interval fold(const float* v, std::uint32_t lanes) {
    Interval r{kInfinity, -kInfinity};
    for (int i = 0; i < 16; ++i)
        if ((lanes >> i) & 1u) r = {std::min(r.lo, v[i]), std::max(r.hi, v[i])};
    return r;
}

}  // namespace

TEST(PacketLanes, SetUpEqualsTheLaneByLaneDefinition) {
    std::mt19937 rng(17);
    for (int round = 0; round < 3000; ++round) {
        const Packet16 p = random_packet(rng, round);
        const PacketLanes l = packet_lanes(p);
        ASSERT_EQ(l.valid, p.active & 0xFFFFu & segment_lanes(p)) << round;
        const float* dir[3] = {p.dir_x, p.dir_y, p.dir_z};
        std::uint32_t flat = 0;
        for (int i = 0; i < 16; ++i) {
            const float speed = std::sqrt(p.dir_x[i] * p.dir_x[i] + p.dir_y[i] * p.dir_y[i] + p.dir_z[i] * p.dir_z[i]);
            ASSERT_EQ(bits(l.speed[i]), bits(speed)) << round << " lane " << i;
            for (int k = 0; k < 3; ++k) {
                ASSERT_EQ(bits(l.unit[k][i]), bits(dir[k][i] * (1.0f / speed))) << round << " lane " << i;
                ASSERT_EQ((l.negative[k] >> i) & 1u, std::signbit(dir[k][i]) ? 1u : 0u) << round;
                if (!(std::fabs(dir[k][i]) >= FLT_MIN)) flat |= 1u << i;
            }
        }
        ASSERT_EQ(l.flat, flat & l.valid) << round;
    }
}

TEST(PacketLanes, RangesAndFarthestEqualTheFolds) {
    std::mt19937 rng(18);
    for (int round = 0; round < 3000; ++round) {
        const Packet16 p = random_packet(rng, round);
        const PacketLanes l = packet_lanes(p);
        const std::uint32_t lanes = l.valid & ~l.flat;
        if (lanes == 0) continue;
        const GroupRanges g = group_ranges(p, l, lanes);
        const float* org[3] = {p.org_x, p.org_y, p.org_z};
        for (int k = 0; k < 3; ++k) {
            const Interval o = fold(org[k], lanes), d = fold(l.unit[k], lanes);
            ASSERT_EQ(bits(g.org[k].lo), bits(o.lo)) << round;
            ASSERT_EQ(bits(g.org[k].hi), bits(o.hi)) << round;
            ASSERT_EQ(bits(g.unit[k].lo), bits(d.lo)) << round;
            ASSERT_EQ(bits(g.unit[k].hi), bits(d.hi)) << round;
            const Interval r = lane_range(org[k], lanes);
            ASSERT_EQ(bits(r.lo), bits(o.lo)) << round;
            ASSERT_EQ(bits(r.hi), bits(o.hi)) << round;
        }
        float far = -kInfinity;
        for (int i = 0; i < 16; ++i)
            if ((lanes >> i) & 1u) far = std::max(far, p.tfar[i] * l.speed[i]);
        ASSERT_EQ(bits(farthest_distance(p.tfar, l.speed, lanes)), bits(far)) << round;
    }
}

TEST(PacketLanes, EnterCellEqualsEachLanesCut) {
    std::mt19937 rng(19);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f);
    int kept = 0, dropped = 0;
    for (int round = 0; round < 3000; ++round) {
        const Packet16 p = random_packet(rng, round);
        const PacketLanes l = packet_lanes(p);
        const std::uint32_t lanes = l.valid & ~l.flat;
        if (lanes == 0) continue;
        Box box;
        for (int k = 0; k < 3; ++k) {
            const float a = u(rng), b = u(rng);
            box.lower[k] = std::min(a, b);
            box.upper[k] = std::max(a, b);
        }
        const float pad = round % 2 ? 1e-6f : 0.0f;
        const CellEntry e = enter_cell(p, lanes, l.speed, box, pad);
        // Lane by lane: the segment in distance along the line, cut by each slab.
        const float* org[3] = {p.org_x, p.org_y, p.org_z};
        const float* dir[3] = {p.dir_x, p.dir_y, p.dir_z};
        std::uint32_t want = 0;
        float c0 = kInfinity, c1 = -kInfinity, near = kInfinity;
        Interval o[3], inv[3];
        for (int k = 0; k < 3; ++k) o[k] = inv[k] = {kInfinity, -kInfinity};
        for (int i = 0; i < 16; ++i) {
            if (!((lanes >> i) & 1u)) continue;
            const float s = l.speed[i], tnear = p.tnear[i] * s;
            float enter = tnear, exit = p.tfar[i] * s;
            for (int k = 0; k < 3; ++k) {
                const float r = s / dir[k][i];
                const float a = (box.lower[k] - org[k][i]) * r, b = (box.upper[k] - org[k][i]) * r;
                const bool swap = a > b;
                const float lo = swap ? b : a, hi = swap ? a : b;
                enter = enter < lo ? lo : enter;  // smax: (enter < lo) ? lo : enter
                exit = hi < exit ? hi : exit;     // smin: (hi < exit) ? hi : exit
                o[k] = {std::min(o[k].lo, org[k][i]), std::max(o[k].hi, org[k][i])};
                inv[k] = {std::min(inv[k].lo, r), std::max(inv[k].hi, r)};
            }
            const float slack = (std::fabs(enter) + std::fabs(exit)) * kRelativePad + pad;
            if (enter > exit + slack) continue;
            want |= 1u << i;
            c0 = std::min(c0, enter);
            c1 = std::max(c1, exit);
            near = std::min(near, tnear);
        }
        ASSERT_EQ(e.lanes, want) << round;
        kept += __builtin_popcount(want);
        dropped += __builtin_popcount(lanes & ~want);
        for (int k = 0; k < 3; ++k) {
            ASSERT_EQ(bits(e.org[k].lo), bits(o[k].lo)) << round;
            ASSERT_EQ(bits(e.org[k].hi), bits(o[k].hi)) << round;
            ASSERT_EQ(bits(e.inv[k].lo), bits(inv[k].lo)) << round;
            ASSERT_EQ(bits(e.inv[k].hi), bits(inv[k].hi)) << round;
        }
        if (want == 0) continue;
        ASSERT_EQ(bits(e.c0), bits(c0)) << round;
        ASSERT_EQ(bits(e.c1), bits(c1)) << round;
        ASSERT_EQ(bits(e.near), bits(near)) << round;
    }
    EXPECT_GT(kept, 1000);
    EXPECT_GT(dropped, 1000);
}
