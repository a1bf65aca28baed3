// Termination (4) of the entry-point search: the first candidate is a flat leaf completely covered by
// its triangles and every ray of the beam crosses it inside the face within its segment, so no ray
// can see past it: the leaf is the entry point although potential leaves lie behind it. Not when the
// beam's rectangle exceeds the face, when some segment ends before the face, or when the triangles
// overlap or leave a gap (then the leaf is not covered).
#include <gtest/gtest.h>

#include "hand_tree.hpp"
#include "mlrta/entry_point_search.hpp"
#include "mlrta/entry_point_trace.hpp"

using namespace beamtrace;
using namespace beamtrace::mlrta;
using namespace beamtrace::mlrta::test;

namespace {

// Scene box [0,2] x [0,1] x [0,10]:
//   0: x < 1 | x >= 1
//   1:   z < 3 | z >= 3
//   2:     z < 3 | z = 3 (node 2 splits again at 3)
//   3:       empty leaf, z in [0, 3]
//   4:       flat leaf z = 3, x and y in [0, 1], holding `face` (two triangles)
//   5:     leaf z in [3, 10] with a quad at z = 6 (a potential leaf behind the face)
//   6:   leaf x in [1, 2] with a quad at z = 6
enum class Face { quad, overlapping, gap };
// kLowerHalf: the entry point of beams within x < 1 that do not stop at the face.
constexpr std::uint32_t kFlatLeaf = 4, kRoot = 0, kLowerHalf = 1, kFirstBehind = 2;

std::shared_ptr<const Mlrta::Impl> flat_leaf_tree(Face face, EpSearch order) {
    HandTree h({0, 0, 0}, {2, 1, 10});
    std::uint32_t a = 0, b = 0;
    switch (face) {
        case Face::quad:  // [0,1]^2 split along its diagonal
            a = h.triangle({0, 0, 3}, {1, 0, 3}, {1, 1, 3});
            b = h.triangle({0, 0, 3}, {1, 1, 3}, {0, 1, 3});
            break;
        case Face::overlapping:  // areas add up to the face's, but the halves overlap (and leave a hole)
            a = h.triangle({0, 0, 3}, {1, 0, 3}, {1, 1, 3});
            b = h.triangle({0, 0, 3}, {1, 0, 3}, {0, 1, 3});
            break;
        case Face::gap:  // a thin wedge between y = x and y = x / 0.9 is not covered
            a = h.triangle({0, 0, 3}, {1, 0, 3}, {1, 1, 3});
            b = h.triangle({0, 0, 3}, {0.9f, 1, 3}, {0, 1, 3});
            break;
    }
    auto quad = [&](float x0, float x1) {
        return std::vector<std::uint32_t>{h.triangle({x0, 0.05f, 6}, {x1, 0.05f, 6}, {x1, 0.95f, 6}),
                                          h.triangle({x0, 0.05f, 6}, {x1, 0.95f, 6}, {x0, 0.95f, 6})};
    };
    const std::vector<std::uint32_t> behind = quad(0.05f, 0.95f), beside = quad(1.05f, 1.95f);
    // Written bottom up, as in the map above.
    const auto node2 = [&] {
        h.inner(
            2, 3.0f, [&] { h.leaf({}); },
            [&] {
                h.leaf({a, b});
            });
    };
    const auto node1 = [&] { h.inner(2, 3.0f, node2, [&] { h.leaf(behind); }); };
    h.inner(0, 1.0f, node1, [&] { h.leaf(beside); });
    MlrtaSettings s;
    s.experimental.ep_search = order;
    return h.mlrta(s);
}

// 16 rays up the z axis from z = -1, origins around (x, y) within +-0.02, leaning slightly to +x +y.
Packet16 upward(float x, float y, float tfar = kInfinity) {
    Packet16 p;
    for (int i = 0; i < 16; ++i) {
        const float ox = x - 0.02f + 0.04f * float(i % 4) / 3.0f, oy = y - 0.02f + 0.04f * float(i / 4) / 3.0f;
        p.set_ray(i, Ray{{ox, oy, -1.0f}, 0.0f, {0.001f + 0.0001f * float(i), 0.002f, 1.0f}, tfar});
    }
    p.active = 0xFFFFu;
    return p;
}

EntryPoint search(const Mlrta::Impl& m, const Packet16& p) {
    Beam b;
    b.set_scene_scale(m.kd().bounds);
    b.add(p);
    std::uint64_t steps = 0;
    return entry_point_search(m, b, root_entry(m), steps);
}

void expect_exact_from(const Mlrta::Impl& m, const Packet16& p, const EntryPoint& ep) {
    PacketHits16 hits;
    trace_packet<false, false>(m, p, ep, &hits, nullptr, nullptr);
    for (int i = 0; i < 16; ++i) EXPECT_TRUE(same_hit(m.tree, p.ray(i), hits.hit(i))) << "lane " << i;
}

const EpSearch kOrders[] = {EpSearch::bifurcation_stack, EpSearch::top_down};

}  // namespace

TEST(MlrtaCoveredLeaf, QuadCoversTheFlatLeaf) {
    const auto m = flat_leaf_tree(Face::quad, EpSearch::top_down);
    ASSERT_EQ(m->kd().nodes.size(), 7u);
    EXPECT_EQ(m->covered_leaf[kFlatLeaf], 1);
    for (std::uint32_t n : {0u, 1u, 2u, 3u, 5u, 6u}) EXPECT_EQ(m->covered_leaf[n], 0) << "node " << n;
    const Box face = node_box(m->kd(), kFlatLeaf);
    EXPECT_EQ(face.lower, (Float3{0, 0, 3}));
    EXPECT_EQ(face.upper, (Float3{1, 1, 3}));
}

TEST(MlrtaCoveredLeaf, OverlapOrGapIsNotCovered) {
    EXPECT_EQ(flat_leaf_tree(Face::overlapping, EpSearch::top_down)->covered_leaf[kFlatLeaf], 0);
    EXPECT_EQ(flat_leaf_tree(Face::gap, EpSearch::top_down)->covered_leaf[kFlatLeaf], 0);
}

TEST(MlrtaCoveredLeaf, BeamCrossingInsideTheFaceStopsThere) {
    for (EpSearch order : kOrders) {
        const auto m = flat_leaf_tree(Face::quad, order);
        for (float x : {0.1f, 0.5f, 0.9f}) {
            const Packet16 p = upward(x, 0.5f);
            const EntryPoint ep = search(*m, p);
            EXPECT_FALSE(ep.misses);
            EXPECT_EQ(ep.node, kFlatLeaf) << "x " << x << " order " << int(order);
            expect_exact_from(*m, p, ep);
        }
    }
}

TEST(MlrtaCoveredLeaf, BeamExceedingTheFaceDoesNotStop) {
    for (EpSearch order : kOrders) {
        const auto m = flat_leaf_tree(Face::quad, order);
        // Some rays cross z = 3 beyond x = 1, beside the face: they go on to the quad at z = 6.
        const Packet16 p = upward(1.0f, 0.5f);
        const EntryPoint ep = search(*m, p);
        EXPECT_EQ(ep.node, kRoot) << "order " << int(order);
        expect_exact_from(*m, p, ep);
        int beside = 0;
        for (int i = 0; i < 16; ++i) beside += m->tree.intersect(p.ray(i)).triangle >= kFirstBehind + 2;
        EXPECT_GT(beside, 0);
    }
}

TEST(MlrtaCoveredLeaf, SegmentsEndingBeforeTheFaceDoNotStop) {
    for (EpSearch order : kOrders) {
        const auto m = flat_leaf_tree(Face::quad, order);
        Packet16 p = upward(0.5f, 0.5f);
        for (int i = 0; i < 16; ++i) p.tfar[i] = i == 7 ? 3.5f : 20.0f;  // one ray ends at z = 2.5
        const EntryPoint ep = search(*m, p);
        EXPECT_EQ(ep.node, kLowerHalf) << "order " << int(order);
        expect_exact_from(*m, p, ep);
    }
}

TEST(MlrtaCoveredLeaf, OverlappingOrGappedTrianglesDoNotStop) {
    for (EpSearch order : kOrders)
        for (Face face : {Face::overlapping, Face::gap}) {
            const auto m = flat_leaf_tree(face, order);
            // Inside the face, over the uncovered part: rays there do reach the quad at z = 6.
            const Packet16 p = face == Face::gap ? upward(0.45f, 0.48f) : upward(0.3f, 0.85f);
            const EntryPoint ep = search(*m, p);
            EXPECT_EQ(ep.node, kLowerHalf) << "order " << int(order);
            expect_exact_from(*m, p, ep);
            int behind = 0;
            for (int i = 0; i < 16; ++i) {
                const Hit hit = m->tree.intersect(p.ray(i));
                behind += hit.hit() && hit.triangle >= kFirstBehind;
            }
            EXPECT_GT(behind, 0) << "some ray passes through the uncovered part";
        }
}
