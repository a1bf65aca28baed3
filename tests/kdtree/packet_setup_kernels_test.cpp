// The per-packet set-up of interval traversal in every instruction set's kernels (PacketKernels::setup:
// SSE4.2 4, AVX2 8, AVX-512 16 lanes a step) against the references (the scalar table: the SSE
// functions of packet_lanes.hpp, one_origin_frustum.hpp, watertight_ray.hpp, lane_box_test.hpp), bit
// for bit: every output of every part, on random packets with inactive lanes, zero, tiny, huge and
// infinite components, NaNs, rays that describe no segment, shared origins, and ranges whose least or
// largest value is +0 in some lanes and -0 in others (where the order of a fold over the lanes shows).
// Instruction sets this CPU lacks are skipped.
#include <gtest/gtest.h>

#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "common/ray_validity.hpp"
#include "kdtree/packet/packet_kernels.hpp"
#include "simd/isa.hpp"

using namespace beamtrace;
using namespace beamtrace::kdtree;

namespace {

std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }

#define EXPECT_SAME_FLOAT(a, b, what) ASSERT_EQ(bits(a), bits(b)) << what << ": " << (a) << " against " << (b)

Packet16 random_packet(std::mt19937& rng, int round) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const float odd[] = {0.0f, -0.0f, 1e-39f, -1e-30f, 3e38f, -FLT_MAX, kInfinity, -kInfinity, NAN};
    Packet16 p;
    const float spread = round % 3 == 0 ? 1.0f : 0.05f;  // incoherent or coherent
    const float base[3] = {u(rng), u(rng), u(rng)};
    for (int i = 0; i < 16; ++i) {
        p.org_x[i] = u(rng) * 2.0f;
        p.org_y[i] = u(rng) * 2.0f;
        p.org_z[i] = u(rng) * 2.0f;
        p.dir_x[i] = base[0] + spread * u(rng);
        p.dir_y[i] = base[1] + spread * u(rng);
        p.dir_z[i] = (base[2] + spread * u(rng)) * (round % 5 == 0 ? 1e6f : 1.0f);
        p.tnear[i] = std::max(0.0f, u(rng));
        p.tfar[i] = i % 5 == 0 ? kInfinity : p.tnear[i] + 3.0f * (u(rng) + 1.0f);
    }
    switch (round % 6) {
        case 1:  // one origin: the frustum's path
            for (int i = 1; i < 16; ++i) p.org_x[i] = p.org_x[0], p.org_y[i] = p.org_y[0], p.org_z[i] = p.org_z[0];
            break;
        case 2:  // +0 and -0 as the least origin and direction component in some lanes
            for (int i = 0; i < 16; ++i) {
                p.org_x[i] = rng() % 3 ? (rng() % 2 ? 0.0f : -0.0f) : 1.0f + u(rng);
                p.dir_y[i] = rng() % 3 ? (rng() % 2 ? 0.0f : -0.0f) : 1.0f + u(rng);
            }
            break;
        case 3:  // the same as the largest
            for (int i = 0; i < 16; ++i) {
                p.org_y[i] = rng() % 3 ? (rng() % 2 ? 0.0f : -0.0f) : -1.0f + u(rng);
                p.dir_z[i] = rng() % 3 ? (rng() % 2 ? 0.0f : -0.0f) : -1.0f + u(rng);
            }
            break;
        case 4:  // odd values anywhere
            for (int i = 0; i < 16; ++i) {
                float* f[8] = {&p.org_x[i], &p.org_y[i], &p.org_z[i], &p.dir_x[i],
                               &p.dir_y[i], &p.dir_z[i], &p.tnear[i], &p.tfar[i]};
                for (float* v : f)
                    if (rng() % 6 == 0) *v = odd[rng() % std::size(odd)];
            }
            break;
        default:
            break;
    }
    if (round % 7 == 3) p.tfar[(round + 3) % 16] = -1.0f;  // no segment
    p.active = round % 4 == 0 ? 0xFFFFu : std::uint32_t(rng()) & 0xFFFFu;
    return p;
}

// Every field of the set-up's outputs, bit for bit.
void expect_same(const PacketLanes& a, const PacketLanes& b, const std::string& at) {
    for (int i = 0; i < 16; ++i) {
        EXPECT_SAME_FLOAT(a.speed[i], b.speed[i], at + " speed, lane " + std::to_string(i));
        for (int k = 0; k < 3; ++k) EXPECT_SAME_FLOAT(a.unit[k][i], b.unit[k][i], at + " unit, lane " + std::to_string(i));
    }
    ASSERT_EQ(a.valid, b.valid) << at;
    ASSERT_EQ(a.flat, b.flat) << at;
    for (int k = 0; k < 3; ++k) ASSERT_EQ(a.negative[k], b.negative[k]) << at;
}
void expect_same(const Interval& a, const Interval& b, const std::string& at) {
    EXPECT_SAME_FLOAT(a.lo, b.lo, at + " lo");
    EXPECT_SAME_FLOAT(a.hi, b.hi, at + " hi");
}
void expect_same(const CellEntry& a, const CellEntry& b, const std::string& at) {
    ASSERT_EQ(a.lanes, b.lanes) << at;
    EXPECT_SAME_FLOAT(a.c0, b.c0, at + " c0");
    EXPECT_SAME_FLOAT(a.c1, b.c1, at + " c1");
    EXPECT_SAME_FLOAT(a.near, b.near, at + " near");
    for (int k = 0; k < 3; ++k) {
        expect_same(a.org[k], b.org[k], at + " org");
        expect_same(a.inv[k], b.inv[k], at + " inv");
    }
}
void expect_same(const OneOriginFrustum& a, const OneOriginFrustum& b, const std::string& at) {
    ASSERT_EQ(a.valid, b.valid) << at;
    ASSERT_EQ(a.m, b.m) << at;
    ASSERT_EQ(a.j0, b.j0) << at;
    ASSERT_EQ(a.j1, b.j1) << at;
    EXPECT_SAME_FLOAT(a.sm, b.sm, at + " sm");
    for (int k = 0; k < 3; ++k) {
        EXPECT_SAME_FLOAT(a.origin[k], b.origin[k], at + " origin");
        expect_same(a.slope[k], b.slope[k], at + " slope");
    }
    EXPECT_SAME_FLOAT(a.reach, b.reach, at + " reach");
}
void expect_same(const WatertightPacket16& a, const WatertightPacket16& b, const std::string& at) {
    const float* fa[11] = {a.org_x, a.org_y, a.org_z, a.kx, a.ky, a.kz, a.sx, a.sy, a.sz, a.tnear, a.tfar};
    const float* fb[11] = {b.org_x, b.org_y, b.org_z, b.kx, b.ky, b.kz, b.sx, b.sy, b.sz, b.tnear, b.tfar};
    for (int k = 0; k < 11; ++k)
        for (int i = 0; i < 16; ++i)
            EXPECT_SAME_FLOAT(fa[k][i], fb[k][i], at + " watertight field " + std::to_string(k) + ", lane " + std::to_string(i));
    ASSERT_EQ(a.active, b.active) << at;
    ASSERT_EQ(a.same_axes, b.same_axes) << at;
    ASSERT_EQ(a.same_origin, b.same_origin) << at;
    ASSERT_EQ(a.first, b.first) << at;
    for (int k = 0; k < 3; ++k) ASSERT_EQ(a.axis[k], b.axis[k]) << at;
}
void expect_same(const LaneBoxRays& a, const LaneBoxRays& b, const std::string& at) {
    for (int i = 0; i < 16; ++i) {
        for (int k = 0; k < 3; ++k) {
            EXPECT_SAME_FLOAT(a.org[k][i], b.org[k][i], at + " box org, lane " + std::to_string(i));
            EXPECT_SAME_FLOAT(a.inv[k][i], b.inv[k][i], at + " box inv, lane " + std::to_string(i));
        }
        EXPECT_SAME_FLOAT(a.tnear[i], b.tnear[i], at + " box tnear, lane " + std::to_string(i));
    }
    EXPECT_SAME_FLOAT(a.pad, b.pad, at + " pad");
}

// The SIMD instruction sets this CPU has (the others reported as skipped).
std::vector<Isa> isas_to_test() {
    std::vector<Isa> isas;
    for (Isa isa : {Isa::sse42, Isa::avx2, Isa::avx512}) {
        if (isa_available(isa))
            isas.push_back(isa);
        else
            std::printf("%s is not available on this CPU: skipped\n", isa_name(isa));
    }
    return isas;
}

}  // namespace

TEST(PacketSetupKernels, EveryInstructionSetGivesTheReferenceSetUpBitForBit) {
    const PacketSetupKernels& ref = simd::select<PacketKernels>(Isa::scalar).setup;
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f);
    int tested = 0, frusta = 0, kept = 0, zero_ties = 0;
    for (Isa isa : isas_to_test()) {
        const PacketSetupKernels& k = simd::select<PacketKernels>(isa).setup;
        ASSERT_NE(k.lanes, ref.lanes) << isa_name(isa) << " has its own set-up kernels";
        for (int round = 0; round < 6000; ++round) {
            const std::string at = std::string(isa_name(isa)) + " round " + std::to_string(round);
            const Packet16 p = random_packet(rng, round);
            PacketLanes lanes, want_lanes;
            k.lanes(p, lanes);
            ref.lanes(p, want_lanes);
            expect_same(lanes, want_lanes, at);
            // Masks: the coherent lanes (what traversal passes), the active lanes, any lanes.
            const std::uint32_t masks[3] = {lanes.valid & ~lanes.flat, p.active & 0xFFFFu, std::uint32_t(rng()) & 0xFFFFu};
            for (const std::uint32_t mask : masks) {
                if (mask == 0) continue;
                const std::string am = at + " mask " + std::to_string(mask);
                const GroupRanges g = k.group_ranges(p, lanes, mask), want_g = ref.group_ranges(p, lanes, mask);
                for (int a = 0; a < 3; ++a) {
                    expect_same(g.org[a], want_g.org[a], am + " group org");
                    expect_same(g.unit[a], want_g.unit[a], am + " group unit");
                }
                if (bits(want_g.org[0].lo) == bits(-0.0f) || bits(want_g.org[1].hi) == bits(0.0f)) ++zero_ties;
                Box box;
                for (int a = 0; a < 3; ++a) {
                    const float x = u(rng), y = u(rng);
                    box.lower[a] = std::min(x, y);
                    box.upper[a] = std::max(x, y);
                }
                const float pad = round % 2 ? 1e-6f : 0.0f;
                const CellEntry e = k.enter_cell(p, mask, lanes.speed, box, pad);
                const CellEntry want_e = ref.enter_cell(p, mask, lanes.speed, box, pad);
                expect_same(e, want_e, am + " cell");
                kept += __builtin_popcount(want_e.lanes);
                EXPECT_SAME_FLOAT(k.farthest_distance(p.tfar, lanes.speed, mask),
                                  ref.farthest_distance(p.tfar, lanes.speed, mask), am + " farthest");
                const OneOriginFrustum f = k.frustum(p, mask), want_f = ref.frustum(p, mask);
                expect_same(f, want_f, am + " frustum");
                frusta += want_f.valid;
                ++tested;
            }
            WatertightPacket16 w, want_w;
            k.watertight(p, w);
            ref.watertight(p, want_w);
            expect_same(w, want_w, at);
            LaneBoxRays s, want_s;
            k.box_rays(p, 1e-6f, s);
            ref.box_rays(p, 1e-6f, want_s);
            expect_same(s, want_s, at);
            if (HasFatalFailure() || HasFailure()) return;
        }
    }
    // The mix reaches every path (on any CPU with SSE4.2, which the library requires).
    EXPECT_GT(tested, 10000);
    EXPECT_GT(frusta, 1000);
    EXPECT_GT(kept, 10000);
    EXPECT_GT(zero_ties, 1000);
}

// The ranges a beam is made of (packet_set_ranges) over sets of 1 to 9 packets from the generator
// above: every field bit for bit in every instruction set, zeros of both signs and NaNs included,
// with sets where no lane is taken; and the reference against a direct reading of its contract.
TEST(PacketSetupKernels, EveryInstructionSetGivesTheReferenceSetRangesBitForBit) {
    const PacketSetupKernels& ref = simd::select<PacketKernels>(Isa::scalar).setup;
    std::mt19937 rng(29);
    int taken = 0, empty = 0, incoherent = 0, one_origin = 0;
    for (Isa isa : isas_to_test()) {
        const PacketSetupKernels& k = simd::select<PacketKernels>(isa).setup;
        ASSERT_NE(k.set_ranges, ref.set_ranges) << isa_name(isa) << " has its own kernel";
        for (int round = 0; round < 3000; ++round) {
            const std::string at = std::string(isa_name(isa)) + " round " + std::to_string(round);
            std::vector<Packet16> packets;
            const int n = 1 + round % 9;
            for (int i = 0; i < n; ++i) {
                packets.push_back(random_packet(rng, round + i * (round % 2)));  // alike or mixed
                if (round % 13 == 5) packets.back().active = 0;
            }
            if (round % 4 == 1)  // one origin over the set (a camera's packets)
                for (Packet16& p : packets)
                    for (int i = 0; i < 16; ++i) {
                        p.org_x[i] = packets[0].org_x[0];
                        p.org_y[i] = packets[0].org_y[0];
                        p.org_z[i] = packets[0].org_z[0];
                    }
            std::vector<const Packet16*> set;
            for (const Packet16& p : packets) set.push_back(&p);
            PacketSetRanges r, want;
            k.set_ranges(set, r);
            ref.set_ranges(set, want);
            ASSERT_EQ(r.rays, want.rays) << at;
            ASSERT_EQ(r.main_axis, want.main_axis) << at;
            for (int a = 0; a < 3; ++a) {
                EXPECT_SAME_FLOAT(r.first_origin[a], want.first_origin[a], at + " first origin");
                ASSERT_EQ(r.signs[a], want.signs[a]) << at;
                expect_same(r.dir[a], want.dir[a], at + " dir");
                expect_same(r.start[a], want.start[a], at + " start");
            }
            ASSERT_EQ(r.same_origin, want.same_origin) << at;
            ASSERT_EQ(r.zero, want.zero) << at;
            expect_same(r.length, want.length, at + " length");
            expect_same(r.near, want.near, at + " near");
            expect_same(r.far, want.far, at + " far");
            if (HasFatalFailure() || HasFailure()) return;
            // The contract, read directly (once per set, from the reference's answer).
            std::uint32_t rays = 0;
            for (const Packet16& p : packets)
                for (int i = 0; i < 16; ++i) {
                    if (!((p.active >> i) & 1u) || !describes_segment(p.ray(i))) continue;
                    ++rays;
                    const Ray ray = p.ray(i);
                    for (int a = 0; a < 3; ++a) {
                        ASSERT_TRUE(want.dir[a].lo <= ray.dir[a] && ray.dir[a] <= want.dir[a].hi) << at;
                        const float s = ray.org[a] + ray.dir[a] * ray.tnear;
                        ASSERT_TRUE(want.start[a].lo <= s && s <= want.start[a].hi) << at;
                        ASSERT_TRUE(ray.org[a] == want.first_origin[a] || !want.same_origin) << at;
                        ASSERT_TRUE(ray.dir[a] != 0.0f || want.zero) << at;
                        ASSERT_TRUE(want.signs[a] & (std::signbit(ray.dir[a]) ? 1u : 2u)) << at;
                    }
                    const float mag = std::fabs(ray.dir[want.main_axis]), far = ray.tfar * mag;
                    ASSERT_TRUE(std::isnan(far) || (want.far.lo <= far && far <= want.far.hi)) << at;
                }
            ASSERT_EQ(want.rays, rays) << at;
            taken += rays > 0;
            empty += rays == 0;
            incoherent += want.zero || want.signs[0] == 3u || want.signs[1] == 3u || want.signs[2] == 3u;
            one_origin += rays > 1 && want.same_origin;
        }
    }
    EXPECT_GT(taken, 2000);
    EXPECT_GT(empty, 100);
    EXPECT_GT(incoherent, 500);
    EXPECT_GT(one_origin, 100);
}
