// The packet walk of the wide BVH (bvh::occluded_packet, MlrtaExperimental::shadow_bvh): a packet's
// occlusion bits are its rays' single-ray answers on every instruction set, for shadow packets
// (rays ending near one light, the reversed bounds), packets from one origin (the forward bounds),
// incoherent packets and packets with zero direction components (lane by lane), inactive lanes and
// rays that describe no segment; and the kernels of the walk (the bounds, a node's and a leaf's
// interval test) give their scalar references' results bit for bit.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "bvh/wide_bvh.hpp"
#include "bvh/wide_bvh_packet.hpp"
#include "common/ray_validity.hpp"
#include "kdtree/packet/packet_kernels.hpp"
#include "../kdtree/test_scenes.hpp"

using namespace beamtrace;

namespace {

std::vector<Isa> isas() {
    std::vector<Isa> out{Isa::scalar};
    for (Isa isa : {Isa::sse42, Isa::avx2, Isa::avx512})
        if (isa_available(isa)) out.push_back(isa);
    return out;
}

// Packets of several kinds over the scene's box (see the file's comment).
std::vector<Packet16> test_packets(const Box& box, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const auto point = [&](float spread) {
        const Float3 c = box.center(), e = box.upper - box.lower;
        return Float3{c.x + (u(random) - 0.5f) * spread * e.x, c.y + (u(random) - 0.5f) * spread * e.y,
                      c.z + (u(random) - 0.5f) * spread * e.z};
    };
    std::vector<Packet16> packets;
    for (int k = 0; k < 600; ++k) {
        Packet16 p;
        p.active = 0xFFFFu;
        const int kind = k % 5;
        const Float3 light = point(1.5f), origin = point(1.5f), near = point(1.2f);
        for (int i = 0; i < 16; ++i) {
            Ray r;
            if (kind == 0) {  // shadow rays: from points near each other towards a light, ending before it
                const Float3 o = near + Float3{u(random), u(random), u(random)} * (0.02f * box.diagonal());
                r = Ray{o, 1e-4f, light - o, 0.999f};
            } else if (kind == 1) {  // one origin, directions in a narrow cone
                const Float3 d = (near - origin) + Float3{u(random), u(random), u(random)} * (0.05f * box.diagonal());
                r = Ray{origin, 0.0f, d, u(random) < 0.5f ? kInfinity : 0.7f + u(random)};
            } else if (kind == 2) {  // incoherent
                r = Ray{point(1.2f), 0.0f, point(1.2f) - point(1.2f), kInfinity};
            } else if (kind == 3) {  // a zero direction component on some lanes, origins on the scene's planes
                const Float3 o = point(1.0f);
                r = Ray{o, 0.0f, Float3{light.x - o.x, i % 3 == 0 ? 0.0f : light.y - o.y, light.z - o.z}, 1.0f};
            } else {  // shadow rays with lanes off and rays that describe no segment
                const Float3 o = near + Float3{u(random), u(random), u(random)} * (0.02f * box.diagonal());
                r = Ray{o, 1e-4f, light - o, 0.999f};
                if (i == 3) r.tfar = -1.0f;
                if (i == 5) r.dir = Float3{0, 0, 0};
                if (i == 7) r.org.x = std::numeric_limits<float>::quiet_NaN();
            }
            p.set_ray(i, r);
        }
        if (kind == 4) p.active = 0xFFFFu & ~(1u << 9) & ~(1u << 12);
        packets.push_back(p);
    }
    return packets;
}

void expect_single_ray_answers(const Scene& scene, unsigned seed) {
    const auto bvh = bvh::WideBvh::build(scene);
    const std::vector<Packet16> packets = test_packets(scene.bounds(), seed);
    const bvh::WideBvhKernels& reference = bvh::wide_bvh_kernels(Isa::scalar);
    int occluded = 0, lit = 0;
    for (std::size_t k = 0; k < packets.size(); ++k) {
        const Packet16& p = packets[k];
        std::uint32_t want = 0;
        for (int i = 0; i < 16; ++i)
            if (((p.active >> i) & 1u) && reference.occluded(*bvh, p.ray(i)).hit()) want |= 1u << i;
        for (Isa isa : isas()) {
            QueryCounters counters;
            const std::uint32_t got = bvh::occluded_packet(*bvh, p, isa, (k % 2) ? &counters : nullptr);
            ASSERT_EQ(got, want) << isa_name(isa) << " packet " << k << " (kind " << k % 5 << ")";
        }
        occluded += __builtin_popcount(want);
        lit += __builtin_popcount(p.active) - __builtin_popcount(want);
    }
    EXPECT_GT(occluded, 500);
    EXPECT_GT(lit, 500);
}

}  // namespace

TEST(WideBvhPacket, OcclusionBitsAreTheSingleRayAnswersOnRandomSoup) {
    expect_single_ray_answers(test::random_soup(4000, 31), 50);
}

TEST(WideBvhPacket, OcclusionBitsAreTheSingleRayAnswersOnBoxesAlongAxes) {
    expect_single_ray_answers(test::stacked_boxes(80, 24), 51);
}

TEST(WideBvhPacket, KernelsGiveTheReferencesResultsBitForBit) {
    const Scene scene = test::random_soup(3000, 33);
    const auto bvh = bvh::WideBvh::build(scene);
    ASSERT_GT(bvh->stats.inner_nodes, 4u);
    const std::vector<Packet16> packets = test_packets(scene.bounds(), 52);
    const kdtree::PacketKernels& packet = simd::select<kdtree::PacketKernels>(Isa::scalar);
    int bounded = 0;
    for (std::size_t k = 0; k < packets.size(); ++k) {
        const Packet16& p = packets[k];
        kdtree::LaneBoxRays rays;
        packet.setup.box_rays(p, bvh->pad, rays);
        const float* const inv[3] = {rays.inv[0], rays.inv[1], rays.inv[2]};
        const std::uint32_t lanes = p.active & segment_lanes(p);
        bvh::PacketBounds want;
        const bool ok = bvh::packet_bounds_reference(p, lanes, inv, want);
        for (Isa isa : isas()) {
            const bvh::WideBvhKernels& kern = bvh::wide_bvh_kernels(isa);
            bvh::PacketBounds got;
            ASSERT_EQ(kern.packet_bounds(p, lanes, inv, got), ok) << isa_name(isa) << " packet " << k;
            if (!ok) continue;
            for (int a = 0; a < 3; ++a) {
                EXPECT_EQ(got.org_lo[a], want.org_lo[a]);
                EXPECT_EQ(got.org_hi[a], want.org_hi[a]);
                EXPECT_EQ(got.inv_lo[a], want.inv_lo[a]);
                EXPECT_EQ(got.inv_hi[a], want.inv_hi[a]);
                EXPECT_EQ(got.upper_first[a], want.upper_first[a]);
            }
            EXPECT_EQ(got.tnear, want.tnear);
            EXPECT_EQ(got.tfar, want.tfar);
            // Every node's and every leaf's test under these bounds.
            for (std::size_t n = 0; n < bvh->stats.inner_nodes; n += 7) {
                const bvh::WideNode& node = bvh->nodes[n];
                int children = 0;
                while (children < bvh::kWidth && node.child[children] != bvh::kEmpty) ++children;
                ASSERT_EQ(kern.packet_node(want, node, children), bvh::packet_node_reference(want, node, children))
                    << isa_name(isa) << " node " << n;
                for (int c = 0; c < children; ++c) {
                    if (!bvh::is_leaf(node.child[c])) continue;
                    const float* block = bvh->rows.data() + 9 * std::size_t(bvh::leaf_first(node.child[c]));
                    const int count = int(bvh::leaf_count(node.child[c]));
                    ASSERT_EQ(kern.packet_leaf(want, block, count), bvh::packet_leaf_reference(want, block, count))
                        << isa_name(isa) << " node " << n << " leaf " << c;
                }
            }
        }
        bounded += ok;
    }
    EXPECT_GT(bounded, 200);
}
