// Interval traversal of 4x4 packets (section 4.3, the XP search): from the root and from the entry
// point of the packet's own beam, every lane gets exactly the closest hit (and the occlusion answer)
// of the single-ray kd-tree traversal. Random scenes built by KdTree::build; coherent, camera-like,
// divergent and partly inactive packets; zero and negative-zero direction components; shadow rays
// traced from the light with reversed().
#include <gtest/gtest.h>

#include <cmath>

#include "hand_tree.hpp"
#include "mlrta/entry_point_search.hpp"
#include "mlrta/entry_point_trace.hpp"

using namespace beamtrace;
using namespace beamtrace::mlrta;
using namespace beamtrace::mlrta::test;

namespace {

struct World {
    KdTree tree;
    std::shared_ptr<const Mlrta::Impl> m;
    explicit World(const Scene& s, const MlrtaSettings& settings = {})
        : tree(KdTree::build(s)), m(make_mlrta(tree, settings)) {}
};

// 16 rays from around one point (exactly one point if `one_origin`) towards a random point of the
// scene, directions within about half a degree of each other: interval traversal takes them.
Packet16 coherent_packet(Rng& rng, const Box& bounds, bool one_origin) {
    const Float3 e = bounds.extent();
    Float3 org, target;
    for (int k = 0; k < 3; ++k) {
        org[k] = bounds.lower[k] + e[k] * uniform(rng, -0.3f, 1.3f);
        target[k] = bounds.lower[k] + e[k] * uniform(rng, 0.0f, 1.0f);
    }
    const Float3 base = target - org;
    std::vector<Ray> rays = bundle(rng, 16, org, one_origin ? 0.0f : 0.004f, base, 0.01f);
    for (int k = 0; k < 3; ++k)
        if (base[k] == 0.0f) return coherent_packet(rng, bounds, one_origin);
    return packet_of(rays);
}

EntryPoint packet_entry(const Mlrta::Impl& m, const Packet16& p) {
    Beam b;
    b.set_scene_scale(m.kd().bounds);
    b.add(p);
    if (b.empty || !b.coherent) return root_entry(m);
    std::uint64_t steps = 0;
    return entry_point_search(m, b, root_entry(m), steps);
}

// Closest hits and occlusion of every lane from `ep` against the kd-tree; inactive lanes: nothing.
::testing::AssertionResult exact_from(const Mlrta::Impl& m, const Packet16& p, const EntryPoint& ep,
                                      QueryCounters& counters) {
    PacketHits16 hits;
    std::uint32_t occluded = 0xFFFFFFFFu;
    trace_packet<false, true>(m, p, ep, &hits, nullptr, &counters);
    trace_packet<true, true>(m, p, ep, nullptr, &occluded, &counters);
    for (int i = 0; i < 16; ++i) {
        const bool active = (p.active >> i) & 1u;
        if (!active) {
            if (hits.hit(i).hit() || hits.t[i] != kInfinity || ((occluded >> i) & 1u))
                return ::testing::AssertionFailure() << "inactive lane " << i << " reports something";
            continue;
        }
        const ::testing::AssertionResult same = same_hit(m.tree, p.ray(i), hits.hit(i));
        if (!same) return ::testing::AssertionFailure() << "lane " << i << ": " << same.message();
        const ::testing::AssertionResult occ = same_occlusion(m.tree, p.ray(i), (occluded >> i) & 1u);
        if (!occ) return ::testing::AssertionFailure() << "lane " << i << ": " << occ.message();
    }
    if (occluded >> 16) return ::testing::AssertionFailure() << "occlusion bits beyond lane 15";
    return ::testing::AssertionSuccess();
}

}  // namespace

TEST(MlrtaIntervalTraversal, CoherentPacketsFromRootAndEntryPointEqualKdTree) {
    const World w(random_soup(3000, 31));
    Rng rng(32);
    QueryCounters root_counters, ep_counters;
    int deep = 0, hits = 0;
    for (int n = 0; n < 3000; ++n) {
        Packet16 p = coherent_packet(rng, w.m->kd().bounds, n % 2 == 0);
        if (n % 3 == 0)  // finite segments
            for (int i = 0; i < 16; ++i) p.tfar[i] = uniform(rng, 0.2f, 1.5f);
        if (n % 5 == 0)
            for (int i = 0; i < 16; ++i) p.tnear[i] = uniform(rng, 0.0f, 0.3f);
        if (n % 4 == 1)  // directions of very different lengths (t in units of |dir|), same segments
            for (int i = 0; i < 16; ++i) {
                const float scale = std::exp2(uniform(rng, -4.0f, 4.0f));
                p.dir_x[i] *= scale, p.dir_y[i] *= scale, p.dir_z[i] *= scale;
                p.tnear[i] /= scale, p.tfar[i] /= scale;
            }
        ASSERT_TRUE(exact_from(*w.m, p, root_entry(*w.m), root_counters)) << "packet " << n << " from the root";
        const EntryPoint ep = packet_entry(*w.m, p);
        deep += ep.node != 0 && !ep.misses;
        ASSERT_TRUE(exact_from(*w.m, p, ep, ep_counters)) << "packet " << n << " from node " << ep.node;
        for (int i = 0; i < 16; ++i) hits += w.tree.intersect(p.ray(i)).hit();
    }
    EXPECT_EQ(root_counters.single_rays, 0u) << "every packet went through interval traversal";
    EXPECT_GT(root_counters.packet_steps, 3000u * 2);
    EXPECT_GT(deep, 600) << "entry points below the root";
    EXPECT_GT(hits, 3000 * 16 / 4);
}

TEST(MlrtaIntervalTraversal, CameraPacketsEqualKdTree) {
    const World w(box_room(30, 33));
    for (EpSearch order : {EpSearch::bifurcation_stack, EpSearch::top_down}) {
        MlrtaSettings s;
        s.experimental.ep_search = order;
        const auto m = make_mlrta(w.tree, s);
        const Camera cams[] = {
            {{4.1f, 0.7f, 2.3f}, {0.2f, 1.0f, -0.25f}, {0.008f, -0.0016f, 0}, {0, 0.0003f, 0.008f}, 64, 64},
            {{-3.0f, -2.0f, 6.0f}, {1.0f, 0.9f, -0.8f}, {0.004f, -0.0044f, 0}, {0.002f, 0.002f, 0.005f}, 64, 48},
        };
        QueryCounters counters;
        for (const Camera& cam : cams) {
            const std::vector<Packet16> packets = cam.packets();
            for (std::size_t n = 0; n < packets.size(); ++n) {
                ASSERT_TRUE(exact_from(*m, packets[n], root_entry(*m), counters)) << "packet " << n;
                ASSERT_TRUE(exact_from(*m, packets[n], packet_entry(*m, packets[n]), counters)) << "packet " << n;
            }
        }
        EXPECT_GT(counters.packet_steps, 0u);
    }
}

TEST(MlrtaIntervalTraversal, InactiveLanesReportNothing) {
    const World w(random_soup(2000, 34));
    Rng rng(35);
    for (int n = 0; n < 600; ++n) {
        Packet16 p = coherent_packet(rng, w.m->kd().bounds, n % 2 == 0);
        p.active = std::uint32_t(rng()) & 0xFFFFu;
        for (int i = 0; i < 16; ++i)
            if (!((p.active >> i) & 1u)) {  // garbage in inactive lanes
                p.org_x[i] = NAN;
                p.dir_y[i] = n % 2 ? 0.0f : -p.dir_y[i];
                p.tfar[i] = -1.0f;
            }
        QueryCounters counters;
        ASSERT_TRUE(exact_from(*w.m, p, root_entry(*w.m), counters)) << "packet " << n;
        ASSERT_TRUE(exact_from(*w.m, p, packet_entry(*w.m, p), counters)) << "packet " << n;
    }
    Packet16 none = coherent_packet(rng, w.m->kd().bounds, true);
    none.active = 0;
    QueryCounters counters;
    EXPECT_TRUE(exact_from(*w.m, none, root_entry(*w.m), counters));
}

TEST(MlrtaIntervalTraversal, DivergentPacketsEqualKdTree) {
    const World w(random_soup(3000, 36));
    Rng rng(37);
    QueryCounters counters;
    for (int n = 0; n < 800; ++n) {
        Packet16 p = coherent_packet(rng, w.m->kd().bounds, n % 2 == 0);
        // Flip one or two components of some lanes: two to four sign octants in one packet; one
        // packet in four has a single odd lane (a group of one goes alone).
        const int flips = 1 + int(rng() % 2);
        for (int i = 0; i < 16; ++i) {
            const bool odd = n % 4 == 0 ? i == 5 : (i % 4) < 2;
            if (!odd) continue;
            float* dir[3] = {p.dir_x, p.dir_y, p.dir_z};
            for (int f = 0; f < flips; ++f) dir[(n + f) % 3][i] = -dir[(n + f) % 3][i];
        }
        ASSERT_TRUE(exact_from(*w.m, p, root_entry(*w.m), counters)) << "packet " << n;
    }
    EXPECT_GT(counters.packet_steps, 0u);
    EXPECT_GT(counters.single_rays, 0u);
    // Entirely scattered directions.
    for (int n = 0; n < 300; ++n) {
        std::vector<Ray> rays;
        for (int i = 0; i < 16; ++i) {
            const Float3 o{uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, 0, 1)};
            rays.push_back(Ray{o, 0.0f, {uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)}, kInfinity});
        }
        ASSERT_TRUE(exact_from(*w.m, packet_of(rays), root_entry(*w.m), counters)) << "scattered packet " << n;
    }
}

TEST(MlrtaIntervalTraversal, ZeroAndNegativeZeroComponentsEqualKdTree) {
    // Boxes on an integer grid: rays with a zero component run inside split planes.
    const World w(box_room(30, 38));
    Rng rng(39);
    for (int n = 0; n < 800; ++n) {
        Packet16 p = coherent_packet(rng, w.m->kd().bounds, n % 2 == 0);
        const int k = n % 3;
        float* dir[3] = {p.dir_x, p.dir_y, p.dir_z};
        float* org[3] = {p.org_x, p.org_y, p.org_z};
        for (int i : {2, 9, 14}) {
            dir[k][i] = (i + n) % 2 ? 0.0f : -0.0f;
            if (n % 2) org[k][i] = std::round(org[k][i]);  // exactly on a plane of box faces
        }
        QueryCounters counters;
        ASSERT_TRUE(exact_from(*w.m, p, root_entry(*w.m), counters)) << "packet " << n;
        EXPECT_GE(counters.single_rays, 2u * 3u) << "the three lanes went alone (closest hit and occlusion)";
        ASSERT_TRUE(exact_from(*w.m, p, packet_entry(*w.m, p), counters)) << "packet " << n;
    }
}

TEST(MlrtaIntervalTraversal, ReversedRayIsTheSameSegmentFromItsFarEnd) {
    const Ray r{{1, 2, 3}, 0.5f, {0.5f, -0.25f, 2.0f}, 4.0f};
    const Ray v = reversed(r);
    EXPECT_EQ(v.org, (Float3{3.0f, 1.0f, 11.0f}));
    EXPECT_EQ(v.dir, (Float3{-0.5f, 0.25f, -2.0f}));
    EXPECT_EQ(v.tnear, 0.0f);
    EXPECT_EQ(v.tfar, 3.5f);
}

// Shadow rays from points of a small patch to a point light, traced from the light as one beam with
// one origin: the public Mlrta::occluded_packet answers what KdTree::occluded answers for the
// original rays. Points and the light lie in free space (their rounding cannot decide a hit).
TEST(MlrtaIntervalTraversal, ReversedShadowRaysGiveTheSameOcclusion) {
    const Scene scene = random_soup(3000, 40);
    const KdTree tree = KdTree::build(scene);
    const Mlrta mlrta(tree);
    Rng rng(41);
    int occluded = 0, free = 0;
    QueryCounters counters;
    for (int n = 0; n < 1500; ++n) {
        const Float3 light{uniform(rng, -0.5f, 1.5f), uniform(rng, -0.5f, 1.5f), uniform(rng, 1.2f, 2.0f)};
        const Float3 patch{uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, -0.3f, 0.5f)};
        Packet16 shadow, from_light;
        for (int i = 0; i < 16; ++i) {
            const Float3 p = patch + Float3{0.002f * float(i % 4), 0.002f * float(i / 4), 0.0f};
            const Ray r{p, 0.0f, light - p, 1.0f};
            shadow.set_ray(i, r);
            from_light.set_ray(i, reversed(r));
        }
        shadow.active = from_light.active = 0xFFFFu;
        std::uint32_t bits = 0;
        mlrta.occluded(std::span<const Packet16>(&from_light, 1), std::span<std::uint32_t>(&bits, 1),
                       QueryOptions{1, &counters});
        for (int i = 0; i < 16; ++i) {
            const bool got = (bits >> i) & 1u;
            ASSERT_TRUE(same_occlusion(tree, shadow.ray(i), got)) << "packet " << n << " lane " << i;
            (got ? occluded : free) += 1;
        }
    }
    EXPECT_GT(occluded, 1000);
    EXPECT_GT(free, 1000);
    EXPECT_GT(counters.packet_steps, 0u);
}

// Triangle culling (on by default): the frustum test on triangle corners for one-origin packets.
// It may only skip triangles no ray can hit.
TEST(MlrtaIntervalTraversal, TriangleCullingKeepsEveryHit) {
    MlrtaSettings s;
    s.experimental.triangle_culling = true;
    const World w(random_soup(3000, 42), s);
    Rng rng(43);
    QueryCounters on, off;
    MlrtaSettings no_culling;
    no_culling.experimental.triangle_culling = false;
    const auto plain = make_mlrta(w.tree, no_culling);
    for (int n = 0; n < 1500; ++n) {
        Packet16 p = coherent_packet(rng, w.m->kd().bounds, n % 2 == 0);
        if (n % 3 == 0)
            for (int i = 0; i < 16; ++i) p.tfar[i] = uniform(rng, 0.2f, 1.5f);
        ASSERT_TRUE(exact_from(*w.m, p, root_entry(*w.m), on)) << "packet " << n;
        ASSERT_TRUE(exact_from(*plain, p, root_entry(*plain), off)) << "packet " << n;
    }
    EXPECT_LT(on.triangle_tests, off.triangle_tests) << "culling culled something";
}
