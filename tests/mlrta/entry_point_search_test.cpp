// Entry-point search (section 4.1) on a tree built like Figure 6, walked through as in the text:
// 1 -> 21 (bifurcation) -> 31 (one child) -> 41 (bifurcation) -> 51 (one child) -> leaf 61 (the first
// candidate); from the stack 41: 52 -> leaf 63 has potential, 41 becomes the candidate and 64's
// subtree is abandoned; from the stack 21: 32 -> 43 (empty) and 44 -> 54 (potential): the entry point
// is 21. The paper's order (EpSearch::bifurcation_stack) and the default top-down walk must find the
// same entry points. Then beams that see one leaf only, beams that see nothing, and the search from
// a non-root start.
#include <gtest/gtest.h>

#include "hand_tree.hpp"
#include "mlrta/entry_point_search.hpp"
#include "mlrta/entry_point_trace.hpp"

using namespace beamtrace;
using namespace beamtrace::mlrta;
using namespace beamtrace::mlrta::test;

namespace {

// The scene box is [0,1] x [0,1] x [0,10]; the beam travels up z from z = -1 through x, y in about
// [0.47, 0.56]. Splits across x and y put the beam on one side (one child); splits across z are
// crossed (both children), near (lower) child first.
struct Figure6 {
    std::uint32_t n1, n21, n22, n31, n32, n41, n42, n43, n44, n51, n52, n53, n54, n61, n62, n63, n64;
    std::shared_ptr<const Mlrta::Impl> m;
};

// `extra` further levels of z splits below node 82 make the abandoned subtree of 64 larger.
Figure6 figure6(int extra, const MlrtaSettings& settings) {
    HandTree h({0, 0, 0}, {1, 1, 10});
    auto tri = [&](float z, float x0, float y0, float x1, float y1) {
        return h.triangle({x0, y0, z}, {x1, y0, z}, {x0, y1, z});
    };
    Figure6 f{};
    // 82 or a chain of `extra` z splits, each with a leaf holding a triangle across the beam.
    std::function<void(float, float, int)> chain = [&](float z0, float z1, int n) {
        const float mid = 0.5f * (z0 + z1);
        if (n == 0) {
            h.leaf({tri(mid, 0.3f, 0.3f, 0.75f, 0.75f)});
            return;
        }
        h.inner(
            2, mid, [&] { h.leaf({tri(0.5f * (z0 + mid), 0.44f, 0.44f, 0.52f, 0.52f)}); },
            [&] { chain(mid, z1, n - 1); });
    };
    // Written bottom up; every leaf's triangle lies inside the leaf's box.
    const auto n72 = [&] {  // 81, 82
        h.inner(
            2, 4.5f, [&] { h.leaf({tri(4.25f, 0.3f, 0.3f, 0.7f, 0.7f)}); }, [&] { chain(4.5f, 5.0f, extra); });
    };
    const auto n64 = [&] {
        f.n64 = h.inner(
            2, 4.0f, [&] { h.leaf({tri(3.75f, 0.4f, 0.4f, 0.6f, 0.6f)}); }, n72);
    };
    const auto n63 = [&] { f.n63 = h.leaf({h.triangle({0.6f, 0.6f, 3}, {0.45f, 0.6f, 3}, {0.6f, 0.45f, 3})}); };
    const auto n52 = [&] { f.n52 = h.inner(2, 3.5f, n63, n64); };
    const auto n62 = [&] { f.n62 = h.leaf({tri(1.0f, 0.05f, 0.3f, 0.25f, 0.9f)}); };
    const auto n61 = [&] { f.n61 = h.leaf({tri(2.0f, 0.4f, 0.4f, 0.52f, 0.52f)}); };
    const auto n51 = [&] { f.n51 = h.inner(0, 0.3f, n62, n61); };
    const auto n41 = [&] { f.n41 = h.inner(2, 2.5f, n51, n52); };
    const auto n42 = [&] { f.n42 = h.leaf({tri(1.0f, 0.1f, 0.05f, 0.5f, 0.15f)}); };
    const auto n31 = [&] { f.n31 = h.inner(1, 0.2f, n42, n41); };
    const auto n53 = [&] { f.n53 = h.leaf({tri(8.0f, 0.05f, 0.1f, 0.25f, 0.9f)}); };
    const auto n54 = [&] { f.n54 = h.leaf({tri(9.0f, 0.3f, 0.0f, 0.8f, 1.0f)}); };
    const auto n44 = [&] { f.n44 = h.inner(0, 0.3f, n53, n54); };
    const auto n43 = [&] { f.n43 = h.leaf({}); };
    const auto n32 = [&] { f.n32 = h.inner(2, 7.5f, n43, n44); };
    const auto n21 = [&] { f.n21 = h.inner(2, 5.0f, n31, n32); };
    const auto n22 = [&] { f.n22 = h.leaf({tri(5.0f, 0.85f, 0.1f, 0.95f, 0.9f)}); };
    f.n1 = h.inner(0, 0.8f, n21, n22);
    f.m = h.mlrta(settings);
    return f;
}

MlrtaSettings with(EpSearch order, FrustumTest test = FrustumTest::inverse) {
    MlrtaSettings s;
    s.experimental.ep_search = order;
    s.experimental.frustum_test = test;
    return s;
}

const EpSearch kOrders[] = {EpSearch::bifurcation_stack, EpSearch::top_down};

// 16 rays from z = -1 up the z axis, origins spread over [0.47, 0.53]^2 (or one origin), directions
// leaning slightly towards +x and +y.
Packet16 upward_packet(bool one_origin = false, float tfar = kInfinity, float z0 = -1.0f) {
    Packet16 p;
    for (int i = 0; i < 16; ++i) {
        const float ox = one_origin ? 0.5f : 0.47f + 0.06f * float(i % 4) / 3.0f;
        const float oy = one_origin ? 0.5f : 0.47f + 0.06f * float(i / 4) / 3.0f;
        const float dx = 0.001f + 0.001f * float((i * 7) % 16) / 15.0f,
                    dy = 0.001f + 0.001f * float((i * 5) % 16) / 15.0f;
        p.set_ray(i, Ray{{ox, oy, z0}, 0.0f, {dx, dy, 1.0f}, tfar});
    }
    p.active = 0xFFFFu;
    return p;
}

Beam beam_of(const Mlrta::Impl& m, const Packet16& p) {
    Beam b;
    b.set_scene_scale(m.kd().bounds);
    b.add(p);
    return b;
}

EntryPoint search(const Mlrta::Impl& m, const Packet16& p, std::uint64_t& steps) {
    steps = 0;
    return entry_point_search(m, beam_of(m, p), root_entry(m), steps);
}

// Interval traversal from the entry point finds, lane by lane, what the kd-tree finds from the root.
void expect_exact_from(const Mlrta::Impl& m, const Packet16& p, const EntryPoint& ep) {
    PacketHits16 hits;
    QueryCounters counters;
    trace_packet<false, true>(m, p, ep, &hits, nullptr, &counters);
    EXPECT_EQ(counters.single_rays, 0u) << "the packet went through interval traversal";
    for (int i = 0; i < 16; ++i) EXPECT_TRUE(same_hit(m.tree, p.ray(i), hits.hit(i))) << "lane " << i;
}

}  // namespace

TEST(MlrtaEntryPointSearch, Figure6WalkThroughEndsAtNode21) {
    const Figure6 f = figure6(0, with(EpSearch::bifurcation_stack));
    const Packet16 p = upward_packet();
    std::uint64_t steps = 0;
    const EntryPoint ep = search(*f.m, p, steps);
    EXPECT_FALSE(ep.misses);
    EXPECT_EQ(ep.node, f.n21);
    EXPECT_EQ(ep.box.lower, (Float3{0, 0, 0}));
    EXPECT_EQ(ep.box.upper, (Float3{0.8f, 1, 10}));
    // Visited: 1, 21, 31, 41, 51, 61 | 52, 63 | 32, 43, 44, 54. Not: 22, 42, 62 (culled), 64's subtree
    // (abandoned), 53 (culled).
    EXPECT_EQ(steps, 12u);
    EXPECT_LT(steps, f.m->kd().nodes.size());
    expect_exact_from(*f.m, p, ep);
}

TEST(MlrtaEntryPointSearch, Figure6TopDownFindsNode21InFewerSteps) {
    const Figure6 f = figure6(0, with(EpSearch::top_down));
    const Packet16 p = upward_packet();
    std::uint64_t steps = 0;
    const EntryPoint ep = search(*f.m, p, steps);
    EXPECT_EQ(ep.node, f.n21);
    // 1, 21 | near of 21 up to its first potential leaf: 31, 41, 51, 61 | far of 21: 32, 43, 44, 54.
    EXPECT_EQ(steps, 10u);
    expect_exact_from(*f.m, p, ep);
}

TEST(MlrtaEntryPointSearch, Figure6AbandonedSubtreeIsNotVisited) {
    for (EpSearch order : kOrders) {
        const Figure6 small = figure6(0, with(order)), large = figure6(30, with(order));
        EXPECT_GT(large.m->subtree_nodes[large.n64], small.m->subtree_nodes[small.n64] + 50);
        std::uint64_t steps_small = 0, steps_large = 0;
        const EntryPoint a = search(*small.m, upward_packet(), steps_small);
        const EntryPoint b = search(*large.m, upward_packet(), steps_large);
        EXPECT_EQ(a.node, small.n21);
        EXPECT_EQ(b.node, large.n21);
        EXPECT_EQ(steps_large, steps_small) << "64's subtree (every leaf of it a potential one) was searched";
        expect_exact_from(*large.m, upward_packet(), b);
    }
}

TEST(MlrtaEntryPointSearch, Figure6WithTheDirectFrustumTest) {
    for (EpSearch order : kOrders) {
        const Figure6 f = figure6(0, with(order, FrustumTest::direct));
        const Packet16 p = upward_packet(true);
        std::uint64_t steps = 0;
        const EntryPoint ep = search(*f.m, p, steps);
        EXPECT_EQ(ep.node, f.n21);
        EXPECT_EQ(steps, order == EpSearch::bifurcation_stack ? 12u : 10u);
        expect_exact_from(*f.m, p, ep);
    }
}

TEST(MlrtaEntryPointSearch, Figure6FromAboveAlsoEndsAtNode21) {
    // The same beam travelling down from z = 11: the far children along z come first now; the first
    // candidate is 54 and the stack brings the search back up to 21.
    Packet16 p = upward_packet(false, kInfinity, 11.0f);
    for (int i = 0; i < 16; ++i) p.dir_z[i] = -1.0f;
    for (EpSearch order : kOrders) {
        const Figure6 f = figure6(0, with(order));
        std::uint64_t steps = 0;
        const EntryPoint ep = search(*f.m, p, steps);
        EXPECT_EQ(ep.node, f.n21);
        expect_exact_from(*f.m, p, ep);
    }
}

TEST(MlrtaEntryPointSearch, FromANonRootStart) {
    const Packet16 p = upward_packet();
    for (EpSearch order : kOrders) {
        const Figure6 f = figure6(0, with(order));
        std::uint64_t steps = 0;
        const EntryPoint ep = entry_point_search(*f.m, beam_of(*f.m, p), entry_at(*f.m, f.n21), steps);
        EXPECT_EQ(ep.node, f.n21);
        EXPECT_EQ(steps, order == EpSearch::bifurcation_stack ? 11u : 9u);  // node 1 is not visited
    }
}

TEST(MlrtaEntryPointSearch, BeamSeeingOneLeafGetsThatLeaf) {
    for (EpSearch order : kOrders) {
        SCOPED_TRACE(int(order));
        const Figure6 f = figure6(0, with(order));
        std::uint64_t steps = 0;
        // Segments ending at z = 2: only leaf 61 (z up to 2.5) can hold a hit.
        const Packet16 short_rays = upward_packet(false, 3.0f);
        EntryPoint ep = search(*f.m, short_rays, steps);
        EXPECT_FALSE(ep.misses);
        EXPECT_EQ(ep.node, f.n61);
        expect_exact_from(*f.m, short_rays, ep);
        // Segments from z = 2.6 to 3.1: inside leaf 63.
        const Packet16 inside = upward_packet(false, 0.5f, 2.6f);
        ep = search(*f.m, inside, steps);
        EXPECT_EQ(ep.node, f.n63);
        expect_exact_from(*f.m, inside, ep);
    }
}

TEST(MlrtaEntryPointSearch, BeamSeeingNothingMisses) {
    for (EpSearch order : kOrders) {
        SCOPED_TRACE(int(order));
        const Figure6 f = figure6(0, with(order));
        std::uint64_t steps = 0;
        // Pointing away from the scene (down from below it).
        Packet16 away = upward_packet();
        for (int i = 0; i < 16; ++i) away.dir_z[i] = -1.0f;
        EntryPoint ep = search(*f.m, away, steps);
        EXPECT_TRUE(ep.misses);
        EXPECT_EQ(ep.node, 0u);
        // Passing beside the scene along x, beyond x = 1.
        Packet16 beside = upward_packet();
        for (int i = 0; i < 16; ++i) {
            beside.org_x[i] += 1.0f;
            beside.org_z[i] = 5.0f;
            beside.dir_x[i] = 1.0f;
            beside.dir_z[i] = 0.001f;
        }
        ep = search(*f.m, beside, steps);
        EXPECT_TRUE(ep.misses);
        // Segments ending in the empty leaf 43 (z from 5.5 to 7), which lies in front of everything else.
        const Packet16 in_empty = upward_packet(false, 1.5f, 5.5f);
        ep = search(*f.m, in_empty, steps);
        EXPECT_TRUE(ep.misses);
        // A missing entry point traces nothing.
        PacketHits16 hits;
        trace_packet<false, false>(*f.m, in_empty, ep, &hits, nullptr, nullptr);
        for (int i = 0; i < 16; ++i) EXPECT_FALSE(hits.hit(i).hit());
    }
}
