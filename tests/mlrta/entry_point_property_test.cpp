// Entry-point search on trees built by KdTree::build, with random beams. With the paper's tests only
// (leaf boxes): every leaf holding triangles that some ray segment of the beam really passes through
// (exact double-precision slab test) lies in the entry point's subtree, a beam marked `misses` passes
// through no such leaf, and the paper's order (bifurcation stack) and the top-down walk return the
// same node. With triangle culling and blockers (the default): every ray's closest hit lies in a leaf
// of the entry point's subtree, `misses` beams have no hit, and a blocker is hit by every ray.
#include <gtest/gtest.h>

#include "hand_tree.hpp"
#include "mlrta/entry_point_search.hpp"
#include "common/triangle_reference.hpp"
#include "mlrta/entry_point_trace.hpp"

using namespace beamtrace;
using namespace beamtrace::mlrta;
using namespace beamtrace::mlrta::test;

namespace {

struct Leaf {
    std::uint32_t node;
    Box box;
};

std::vector<Leaf> nonempty_leaves(const KdTree::Impl& kd) {
    std::vector<Leaf> out;
    std::vector<Leaf> stack{{0, kd.bounds}};
    while (!stack.empty()) {
        const Leaf n = stack.back();
        stack.pop_back();
        const KdNode& node = kd.nodes[n.node];
        if (node.is_leaf()) {
            if (node.triangle_count() > 0) out.push_back(n);
            continue;
        }
        Leaf lower{n.node + 1, n.box}, upper{node.upper_child(), n.box};
        lower.box.upper[node.axis()] = node.split;
        upper.box.lower[node.axis()] = node.split;
        stack.push_back(lower);
        stack.push_back(upper);
    }
    return out;
}

// A random coherent bundle aimed into the scene box: one origin or several, narrow or wide, with
// finite or infinite segments.
std::vector<Ray> random_beam_rays(Rng& rng, const Box& b) {
    const Float3 e = b.extent();
    Float3 org, target;
    for (int k = 0; k < 3; ++k) {
        org[k] = b.lower[k] + e[k] * uniform(rng, -0.5f, 1.5f);
        target[k] = b.lower[k] + e[k] * uniform(rng, 0.0f, 1.0f);
    }
    Float3 dir = target - org;
    for (int k = 0; k < 3; ++k)
        if (dir[k] == 0.0f) dir[k] = 1e-3f;
    const float spread_org = rng() % 2 ? 0.0f : uniform(rng, 0.0f, 0.05f) * length(e);
    std::vector<Ray> rays = bundle(rng, 2 + int(rng() % 30), org, spread_org, dir, uniform(rng, 0.0f, 0.2f));
    if (rng() % 3 == 0)
        for (Ray& r : rays) r.tfar = uniform(rng, 0.3f, 1.2f);
    return rays;
}

MlrtaSettings settings(EpSearch order, FrustumTest test, bool ep_triangles = false) {
    MlrtaSettings s;
    s.experimental.ep_search = order;
    s.experimental.frustum_test = test;
    s.experimental.ep_triangles = ep_triangles;
    return s;
}

// The first `count` rays: their beam (rays added one by one) lies inside the beam of all of them.
std::vector<Ray> first_rays(const std::vector<Ray>& rays, std::size_t count) {
    return {rays.begin(), rays.begin() + std::ptrdiff_t(std::min(count, rays.size()))};
}

// A leaf below `node` holds triangle `id` and its box, grown by the rounding of a float hit
// distance (`scale`: the size of the coordinates involved), holds point p.
bool hit_below(const KdTree::Impl& kd, const std::vector<Leaf>& leaves, std::uint32_t first, std::uint32_t end,
               std::uint32_t id, const double p[3], double scale) {
    for (const Leaf& leaf : leaves) {
        if (leaf.node < first || leaf.node >= end) continue;
        bool inside = true;
        for (int k = 0; k < 3; ++k) {
            const double slack = 1e-5 * scale;
            inside = inside && p[k] >= leaf.box.lower[k] - slack && p[k] <= leaf.box.upper[k] + slack;
        }
        if (!inside) continue;
        const KdNode& node = kd.nodes[leaf.node];
        for (std::uint32_t j = 0; j < node.triangle_count(); ++j)
            if (kd.triangle_ids[node.offset() + j] == id) return true;
    }
    return false;
}

}  // namespace

TEST(MlrtaEntryPointProperty, EveryLeafARayPassesLiesBelowTheEntryPoint) {
    const KdTree tree = KdTree::build(random_soup(3000, 61));
    const std::vector<Leaf> leaves = nonempty_leaves(detail::Access::impl(tree));
    Rng rng(62);
    struct Case {
        std::vector<Ray> rays;
        std::vector<std::uint32_t> met;  // non-empty leaves some ray passes through
    };
    std::vector<Case> cases;
    for (int n = 0; n < 1000; ++n) {
        Case c{random_beam_rays(rng, detail::Access::impl(tree).bounds), {}};
        if (n % 10 == 0)  // pointing away from the scene's centre: often nothing at all
            for (Ray& r : c.rays) r.dir = r.dir * -1.0f;
        for (const Leaf& leaf : leaves)
            for (const Ray& r : c.rays)
                if (segment_meets_box(r, leaf.box)) {
                    c.met.push_back(leaf.node);
                    break;
                }
        cases.push_back(std::move(c));
    }
    for (FrustumTest test : {FrustumTest::inverse, FrustumTest::direct})
        for (EpSearch order : {EpSearch::bifurcation_stack, EpSearch::top_down}) {
            const auto m = make_mlrta(tree, settings(order, test));
            int below_root = 0, misses = 0;
            for (std::size_t n = 0; n < cases.size(); ++n) {
                const Beam beam = beam_of(cases[n].rays, &detail::Access::impl(tree).bounds);
                ASSERT_TRUE(beam.coherent);
                std::uint64_t steps = 0;
                const EntryPoint ep = entry_point_search(*m, beam, root_entry(*m), steps);
                const std::uint32_t first = ep.node, end = ep.node + m->subtree_nodes[ep.node];
                ASSERT_EQ(ep.box.lower, node_box(detail::Access::impl(tree), ep.node).lower);
                ASSERT_EQ(ep.box.upper, node_box(detail::Access::impl(tree), ep.node).upper);
                below_root += ep.node != 0 && !ep.misses;
                misses += ep.misses;
                for (std::uint32_t leaf : cases[n].met) {
                    ASSERT_FALSE(ep.misses) << "beam " << n << " passes through leaf " << leaf;
                    ASSERT_TRUE(leaf >= first && leaf < end)
                        << "beam " << n << ": leaf " << leaf << " outside the subtree of " << ep.node;
                }
            }
            EXPECT_GT(below_root, 100) << "order " << int(order) << " direct " << int(test);
            EXPECT_GT(misses, 20) << "order " << int(order) << " direct " << int(test);
        }
}

TEST(MlrtaEntryPointProperty, EveryClosestHitLiesBelowTheEntryPoint) {
    // Triangle culling and blockers (the default): leaves the rays pass may lie outside the entry
    // point's subtree, but never the one where a ray finds its closest hit.
    for (const Scene& scene : {random_soup(3000, 71), box_room(30, 72)}) {
        const KdTree tree = KdTree::build(scene);
        const std::vector<Leaf> leaves = nonempty_leaves(detail::Access::impl(tree));
        Rng rng(73);
        for (EpSearch order : {EpSearch::bifurcation_stack, EpSearch::top_down}) {
            const auto m = make_mlrta(tree, settings(order, FrustumTest::inverse, true));
            int below_root = 0, blocked = 0, hits = 0;
            for (int n = 0; n < 1500; ++n) {
                const std::vector<Ray> rays = random_beam_rays(rng, detail::Access::impl(tree).bounds);
                const Beam beam = beam_of(rays, &detail::Access::impl(tree).bounds);
                std::uint64_t steps = 0;
                const EntryPoint ep = entry_point_search(*m, beam, root_entry(*m), steps);
                const std::uint32_t first = ep.node, end = ep.node + m->subtree_nodes[ep.node];
                below_root += ep.node != 0 && !ep.misses;
                blocked += ep.blocked();
                for (const Ray& r : rays) {
                    const Hit h = intersect_brute_force(scene, r);
                    if (ep.blocked()) {
                        TriangleHit th;
                        ASSERT_TRUE(intersect_triangle(make_watertight_ray(r), scene.triangle(ep.blocker), th))
                            << "beam " << n << ": a ray misses the blocker " << ep.blocker;
                        ASSERT_TRUE(th.t >= r.tnear && th.t <= r.tfar) << "beam " << n;
                    }
                    if (!h.hit()) continue;
                    ++hits;
                    ASSERT_FALSE(ep.misses) << "beam " << n << " has a hit on triangle " << h.triangle;
                    const double p[3] = {double(r.org.x) + double(r.dir.x) * h.t,
                                         double(r.org.y) + double(r.dir.y) * h.t,
                                         double(r.org.z) + double(r.dir.z) * h.t};
                    const double scale = 1.0 + length(r.org) + length(r.dir) * double(h.t);
                    ASSERT_TRUE(hit_below(detail::Access::impl(tree), leaves, first, end, h.triangle, p, scale))
                        << "beam " << n << ": the closest hit on " << h.triangle << " is outside the subtree of "
                        << ep.node << " (order " << int(order) << ")";
                }
            }
            EXPECT_GT(below_root, 100) << "order " << int(order);
            EXPECT_GT(blocked, 20) << "order " << int(order);
            EXPECT_GT(hits, 1000) << "order " << int(order);
        }
    }
}

TEST(MlrtaEntryPointProperty, BothOrdersFindTheSameEntryPoint) {
    for (const Scene& scene : {random_soup(3000, 63), box_room(30, 64)}) {
        const KdTree tree = KdTree::build(scene);
        for (FrustumTest test : {FrustumTest::inverse, FrustumTest::direct}) {
            const auto stack = make_mlrta(tree, settings(EpSearch::bifurcation_stack, test));
            const auto top_down = make_mlrta(tree, settings(EpSearch::top_down, test));
            Rng rng(65);
            std::uint64_t steps_stack = 0, steps_top_down = 0;
            for (int n = 0; n < 3000; ++n) {
                const std::vector<Ray> rays = random_beam_rays(rng, detail::Access::impl(tree).bounds);
                const Beam beam = beam_of(rays, &detail::Access::impl(tree).bounds);
                // From the root; then the beam of the first half of the rays from the whole beam's
                // entry point (a sub-tile searching from its parent's entry point).
                const EntryPoint a = entry_point_search(*stack, beam, root_entry(*stack), steps_stack);
                const EntryPoint b = entry_point_search(*top_down, beam, root_entry(*top_down), steps_top_down);
                ASSERT_EQ(a.node, b.node) << "beam " << n;
                ASSERT_EQ(a.misses, b.misses) << "beam " << n;
                if (a.misses) continue;
                const Beam part = beam_of(first_rays(rays, rays.size() / 2 + 1), &detail::Access::impl(tree).bounds);
                const EntryPoint c = entry_point_search(*stack, part, a, steps_stack);
                const EntryPoint d = entry_point_search(*top_down, part, b, steps_top_down);
                ASSERT_EQ(c.node, d.node) << "beam " << n << " part";
                ASSERT_EQ(c.misses, d.misses) << "beam " << n << " part";
                ASSERT_TRUE(c.misses || (c.node >= a.node && c.node < a.node + stack->subtree_nodes[a.node]))
                    << "a part's entry point lies below its whole's";
            }
            EXPECT_LT(steps_top_down, steps_stack) << "direct " << int(test);
        }
    }
}

TEST(MlrtaEntryPointProperty, APartResumedFromItsWholesTrailFindsAValidEntryPoint) {
    // A sub-tile searches from its parent's entry point; with the parent's trail it starts at the
    // parent's first potential leaf, two levels down (a part of a part resumes from the part's
    // trail). The walk skips only leaves that hold nothing for the parent's beam, so the entry point
    // is valid: with the paper's tests every leaf a ray of the part passes lies below it, with
    // triangles (and in the room, whose flat covered leaves end rays) every closest hit does. It is
    // not always the plain search's node (the plain walk decides the skipped nodes with the part's
    // own bounds, which the direct test does not nest inside the whole's), but nearly always.
    for (const bool room : {false, true}) {
        const Scene scene = room ? box_room(30, 82) : random_soup(3000, 81);
        const KdTree tree = KdTree::build(scene);
        const Box& bounds = detail::Access::impl(tree).bounds;
        const std::vector<Leaf> leaves = nonempty_leaves(detail::Access::impl(tree));
        for (bool triangles : {false, true})
            for (FrustumTest test : {FrustumTest::inverse, FrustumTest::direct})
                for (EpSearch order : {EpSearch::bifurcation_stack, EpSearch::top_down}) {
                    const auto m = make_mlrta(tree, settings(order, test, triangles));
                    const std::string where = "triangles " + std::to_string(triangles) + " direct " +
                                              std::to_string(test == FrustumTest::direct) + " order " +
                                              std::to_string(int(order));
                    Rng rng(83);
                    int resumed = 0, same = 0;
                    for (int n = 0; n < 600; ++n) {
                        const std::vector<Ray> rays = random_beam_rays(rng, bounds);
                        SearchTrail trails[2];
                        std::uint64_t steps = 0;
                        EntryPoint start =
                            entry_point_search(*m, beam_of(rays, &bounds), root_entry(*m), steps, nullptr, &trails[0]);
                        int level = 0;
                        for (std::size_t count : {rays.size() / 2 + 1, rays.size() / 4 + 1}) {
                            if (start.misses || !trails[level % 2].valid) break;
                            const Beam part = beam_of(first_rays(rays, count), &bounds);
                            const EntryPoint plain = entry_point_search(*m, part, start, steps);
                            const EntryPoint again = entry_point_search(*m, part, start, steps, &trails[level % 2],
                                                                        &trails[(level + 1) % 2]);
                            ++level;
                            ++resumed;
                            same += plain.node == again.node && plain.misses == again.misses;
                            const std::uint32_t first = again.node, end = again.node + m->subtree_nodes[again.node];
                            for (std::size_t i = 0; i < count; ++i) {
                                const Ray& r = rays[i];
                                if (!triangles && !room) {
                                    for (const Leaf& leaf : leaves)
                                        if (segment_meets_box(r, leaf.box)) {
                                            ASSERT_FALSE(again.misses) << where << " beam " << n << " level " << level;
                                            ASSERT_TRUE(leaf.node >= first && leaf.node < end)
                                                << where << " beam " << n << " level " << level << ": leaf "
                                                << leaf.node << " outside the subtree of " << again.node;
                                        }
                                    continue;
                                }
                                const Hit h = intersect_brute_force(scene, r);
                                if (!h.hit()) continue;
                                ASSERT_FALSE(again.misses) << where << " beam " << n << " level " << level;
                                const double p[3] = {double(r.org.x) + double(r.dir.x) * h.t,
                                                     double(r.org.y) + double(r.dir.y) * h.t,
                                                     double(r.org.z) + double(r.dir.z) * h.t};
                                const double scale = 1.0 + length(r.org) + length(r.dir) * double(h.t);
                                ASSERT_TRUE(
                                    hit_below(detail::Access::impl(tree), leaves, first, end, h.triangle, p, scale))
                                    << where << " beam " << n << " level " << level << ": the closest hit on "
                                    << h.triangle << " is outside the subtree of " << again.node;
                            }
                            start = again;
                        }
                    }
                    EXPECT_GT(resumed, 300) << where;
                    EXPECT_GT(same, resumed * 95 / 100) << where << ": of " << resumed;
                }
    }
}

TEST(MlrtaEntryPointProperty, EveryClosestHitLiesInTheFirstPotentialLeafOrAfterIt) {
    // What interval traversal relies on when it starts at the trail's first potential leaf with the
    // other children of the bifurcations on its path on its stack: every ray's closest hit lies in
    // that leaf or below one of those children.
    for (const Scene& scene : {random_soup(3000, 91), box_room(30, 92)}) {
        const KdTree tree = KdTree::build(scene);
        const Box& bounds = detail::Access::impl(tree).bounds;
        const std::vector<Leaf> leaves = nonempty_leaves(detail::Access::impl(tree));
        for (EpSearch order : {EpSearch::bifurcation_stack, EpSearch::top_down}) {
            const auto m = make_mlrta(tree, settings(order, FrustumTest::inverse, true));
            Rng rng(93);
            int checked = 0, deeper = 0;
            for (int n = 0; n < 1500; ++n) {
                const std::vector<Ray> rays = random_beam_rays(rng, bounds);
                SearchTrail whole_trail, part_trail;
                std::uint64_t steps = 0;
                const EntryPoint whole =
                    entry_point_search(*m, beam_of(rays, &bounds), root_entry(*m), steps, nullptr, &whole_trail);
                const std::size_t half = rays.size() / 2 + 1;
                const EntryPoint part = entry_point_search(*m, beam_of(first_rays(rays, half), &bounds), whole, steps,
                                                           &whole_trail, &part_trail);
                for (int level = 0; level < 2; ++level) {
                    const SearchTrail& trail = level == 0 ? whole_trail : part_trail;
                    if (!trail.valid || (level == 0 ? whole : part).misses) continue;
                    ASSERT_EQ(trail.count > 0 ? trail.bif.at[0].node.node : trail.first.node,
                              (level == 0 ? whole : part).node)
                        << "beam " << n << ": the trail starts at the entry point";
                    deeper += trail.first.node != (level == 0 ? whole : part).node;
                    for (std::size_t i = 0; i < (level == 0 ? rays.size() : half); ++i) {
                        const Ray& r = rays[i];
                        const Hit h = intersect_brute_force(scene, r);
                        if (!h.hit()) continue;
                        ++checked;
                        const double p[3] = {double(r.org.x) + double(r.dir.x) * h.t,
                                             double(r.org.y) + double(r.dir.y) * h.t,
                                             double(r.org.z) + double(r.dir.z) * h.t};
                        const double scale = 1.0 + length(r.org) + length(r.dir) * double(h.t);
                        bool found = hit_below(detail::Access::impl(tree), leaves, trail.first.node,
                                               trail.first.node + 1, h.triangle, p, scale);
                        for (int j = 0; j < trail.count && !found; ++j) {
                            const std::uint32_t other = trail.bif.at[j].other.node;
                            found = hit_below(detail::Access::impl(tree), leaves, other,
                                              other + m->subtree_nodes[other], h.triangle, p, scale);
                        }
                        ASSERT_TRUE(found) << "beam " << n << " level " << level << ": the closest hit on "
                                           << h.triangle << " is before the first potential leaf " << trail.first.node;
                    }
                }
            }
            EXPECT_GT(checked, 1000) << "order " << int(order);
            EXPECT_GT(deeper, 100) << "order " << int(order);
        }
    }
}
