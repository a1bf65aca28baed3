// Tile splitting with secondary rays through the public Mlrta: shadow rays traced from a point light
// (reversed(): one origin per tile, occlusion) and mirror reflections off the floor (many origins,
// tnear > 0, closest hits), with lanes inactive where the primary ray found no surface. Every active
// lane must answer what the kd-tree answers for the very same ray.
#include <gtest/gtest.h>

#include "hand_tree.hpp"

using namespace beamtrace;
using namespace beamtrace::mlrta;
using namespace beamtrace::mlrta::test;

namespace {

const KdTree& room() {
    static const KdTree tree = KdTree::build(box_room(30, 71));
    return tree;
}

// The settings to cover: split factor, tile sizes, frustum test, search order, triangle culling
// (occlusion by the paper's tiles of beams), and then occlusion packets through the wide BVH
// (MlrtaExperimental::shadow_bvh, the default).
std::vector<MlrtaSettings> settings_list() {
    std::vector<MlrtaSettings> out;
    for (int sf : {4, 16})
        for (int its : {32, 128})
            for (int mts : {4, 16})
                for (FrustumTest ft : {FrustumTest::inverse, FrustumTest::direct})
                    for (EpSearch order : {EpSearch::bifurcation_stack, EpSearch::top_down}) {
                        MlrtaSettings s;
                        s.split_factor = sf;
                        s.initial_tile = its;
                        s.min_tile = mts;
                        s.experimental.frustum_test = ft;
                        s.experimental.ep_search = order;
                        s.experimental.triangle_culling = out.size() % 3 == 1;  // mixed in, not a full product
                        s.experimental.stop_when_stuck = out.size() % 5 != 0;
                        s.experimental.shadow_bvh = false;
                        out.push_back(s);
                    }
    out.push_back(MlrtaSettings{});
    return out;
}

// Primary hits of a camera looking down into the room; lanes without a hit are inactive in `make`.
template <class Make>
std::vector<Packet16> secondary(const KdTree& tree, const Camera& cam, Make make) {
    std::vector<Packet16> packets = cam.packets();
    for (Packet16& p : packets) {
        std::uint32_t active = 0;
        for (int i = 0; i < 16; ++i) {
            const Ray r = p.ray(i);
            const Hit h = tree.intersect(r);
            Ray out{};
            if (h.hit() && make(r, h, out)) active |= 1u << i;
            p.set_ray(i, out);
        }
        p.active = active;
    }
    return packets;
}

const Camera kCamera{{1.5f, 1.2f, 3.8f}, {0.5f, 0.6f, -1.0f}, {0.008f, -0.0065f, 0}, {0.003f, 0.004f, 0.0055f}, 96, 72};

}  // namespace

TEST(MlrtaSecondaryRays, ShadowRaysFromAPointLightEqualKdTree) {
    const KdTree& tree = room();
    const Float3 light{6.3f, 6.9f, 3.7f};
    const std::vector<Packet16> shadow = secondary(tree, kCamera, [&](const Ray& r, const Hit& h, Ray& out) {
        const Float3 p = r.org + r.dir * h.t;
        out = reversed(Ray{p, 1e-4f, light - p, 1.0f});  // traced from the light
        return true;
    });
    const PacketGrid grid{shadow.data(), kCamera.width / 4, kCamera.height / 4};
    int lit = 0, dark = 0;
    int run = 0;
    for (const MlrtaSettings& s : settings_list()) {
        const Mlrta mlrta(tree, s);
        std::vector<std::uint32_t> occluded(shadow.size(), 0xFFFFFFFFu);
        QueryCounters counters;
        mlrta.occluded(grid, occluded, QueryOptions{1 + run++ % 2, &counters});
        for (std::size_t p = 0; p < shadow.size(); ++p) {
            ASSERT_EQ(occluded[p] & ~shadow[p].active, 0u) << "inactive lanes of packet " << p;
            for (int i = 0; i < 16; ++i) {
                if (!((shadow[p].active >> i) & 1u)) continue;
                const bool got = (occluded[p] >> i) & 1u;
                ASSERT_TRUE(same_occlusion(tree, shadow[p].ray(i), got)) << "packet " << p << " lane " << i;
                (got ? dark : lit) += 1;
            }
        }
        EXPECT_GT(counters.packet_steps, 0u);
    }
    EXPECT_GT(lit, 1000);
    EXPECT_GT(dark, 1000);
}

TEST(MlrtaSecondaryRays, FloorReflectionsEqualKdTree) {
    const KdTree& tree = room();
    const std::vector<Packet16> mirror = secondary(tree, kCamera, [&](const Ray& r, const Hit& h, Ray& out) {
        if (h.triangle > 1) return false;  // only the room's floor (its first two triangles) is a mirror
        Float3 p = r.org + r.dir * h.t;
        p.z = 0.0f;
        out = Ray{p, 1e-4f, {r.dir.x, r.dir.y, -r.dir.z}, kInfinity};
        return true;
    });
    const PacketGrid grid{mirror.data(), kCamera.width / 4, kCamera.height / 4};
    int active = 0, hits = 0, run = 0;
    for (const Packet16& p : mirror) active += __builtin_popcount(p.active);
    ASSERT_GT(active, 1000) << "the camera sees the floor";
    for (const MlrtaSettings& s : settings_list()) {
        const Mlrta mlrta(tree, s);
        std::vector<PacketHits16> got(mirror.size());
        QueryCounters counters;
        mlrta.intersect(grid, got, QueryOptions{1 + run++ % 2, &counters});
        for (std::size_t p = 0; p < mirror.size(); ++p)
            for (int i = 0; i < 16; ++i) {
                if (!((mirror[p].active >> i) & 1u)) {
                    ASSERT_FALSE(got[p].hit(i).hit()) << "inactive lane " << i << " of packet " << p;
                    continue;
                }
                ASSERT_TRUE(same_hit(tree, mirror[p].ray(i), got[p].hit(i))) << "packet " << p << " lane " << i;
                hits += got[p].hit(i).hit();
            }
        EXPECT_GT(counters.mlrta.ep_steps, 0u);
    }
    EXPECT_GT(hits, 1000);
}
