// The sorted lists (flat and hierarchical, several rules) against the kd-tree's single-ray queries
// and brute force: the same watertight test and the same tie rule (smallest t, then smallest id), so
// every closest hit must equal brute force's bit for bit (t, triangle, u, v) and kd1's (apart from
// kd1's own tie breaks, see expect_kd_answers), and every occlusion answer must be the same.
// The rays are the hard ones for event lists: random, axis-parallel with +0 / -0 components, grazing
// along triangle edges and inside triangle planes, starting exactly on event values (vertex
// coordinates), segments with negative tnear and short tfar; the scenes have many equal coordinates
// (grids of quads, stacked axis-aligned boxes, tetra).
#include <gtest/gtest.h>

#include <bit>
#include <random>
#include <string>

#include "beamtrace/kdtree.hpp"
#include "beamtrace/sorted_lists.hpp"
#include "crsh_test_rays.hpp"
#include "scenes/scene_source.hpp"
#include "test_scenes.hpp"

using namespace beamtrace;

namespace {

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

// Rays along each triangle's edges (from a corner, through the next, the segment reaching behind),
// inside its plane (from a corner towards a point of the plane outside it), and from a corner in a
// random direction; some with exact zero components.
std::vector<Ray> grazing_rays(const Scene& scene, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(scene.triangle_count() - 1));
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        const Triangle& t = scene.triangle(pick(rng));
        const Float3 c[3] = {t.v0, t.v1, t.v2};
        const int k = int(rng() % 3);
        const Float3 a = c[k], b = c[(k + 1) % 3], d = c[(k + 2) % 3];
        Ray r;
        switch (rng() % 4) {
            case 0:  // along an edge, from before its start
                r = Ray{a, -0.5f, b - a, kInfinity};
                break;
            case 1:  // inside the plane, outside the triangle: a + s (b - a) + w (d - a) with s + w > 1
                r = Ray{a, 0.0f, (b - a) * 1.5f + (d - a) * 0.75f, kInfinity};
                break;
            case 2:  // from a point beyond an edge's end back along it
                r = Ray{b + (b - a) * 0.5f, 0.0f, a - b, kInfinity};
                break;
            default:  // from a corner, any direction
                r = Ray{a, 0.0f, Float3{u(rng), u(rng), u(rng)}, kInfinity};
                break;
        }
        if (rng() % 4 == 0) r.dir[int(rng() % 3)] = (rng() % 2) ? 0.0f : -0.0f;
        if (r.dir.x == 0.0f && r.dir.y == 0.0f && r.dir.z == 0.0f) r.dir.z = 1.0f;
        rays.push_back(r);
    }
    return rays;
}

// Origins whose coordinates are those of other triangles' corners (event values on every axis), in
// random and axis directions (some components denormal or tiny), with tnear 0 or negative and some
// short segments.
std::vector<Ray> event_origin_rays(const Scene& scene, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const auto verts = scene.vertices();
    std::uniform_int_distribution<std::size_t> pickv(0, verts.size() - 1);
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        Ray r;
        for (int k = 0; k < 3; ++k) r.org[k] = verts[pickv(rng)][k];
        r.dir = Float3{u(rng), u(rng), u(rng)};
        if (rng() % 3 == 0) {
            const int axis = int(rng() % 3);
            r.dir = Float3{0.0f, -0.0f, 0.0f};
            r.dir[axis] = (rng() % 2) ? 1.0f : -1.0f;
        }
        // Denormal and tiny components (no finite reciprocal; t overflows).
        if (rng() % 6 == 0) r.dir[int(rng() % 3)] = (rng() % 2 ? 1.0f : -1.0f) * (rng() % 2 ? 8.6e-40f : 1e-30f);
        if (r.dir.x == 0.0f && r.dir.y == 0.0f && r.dir.z == 0.0f) r.dir.x = 1.0f;
        if (rng() % 4 == 0) r.tnear = -0.25f * scene.bounds().diagonal() / length(r.dir);
        if (rng() % 4 == 0) r.tfar = 0.1f * scene.bounds().diagonal() / length(r.dir);
        rays.push_back(r);
    }
    return rays;
}

struct RuleCase {
    const char* name;
    SortedListRules rules;
};

std::vector<RuleCase> rule_cases() {
    std::vector<RuleCase> cases;
    SortedListRules flat;
    flat.flat = true;
    cases.push_back({"flat", flat});
    cases.push_back({"default", SortedListRules{}});
    SortedListRules fine;
    fine.leaf_objects = 1;
    fine.grid[0] = 3;
    fine.grid[1] = 1;
    fine.grid[2] = 2;
    cases.push_back({"grid 3x1x2 leaf 1", fine});
    SortedListRules wide;
    wide.leaf_objects = 16;
    wide.grid[0] = wide.grid[1] = wide.grid[2] = 4;
    wide.special_cell_fraction = 0.1f;
    cases.push_back({"grid 4 leaf 16 special 0.1", wide});
    return cases;
}

// Every answer of the lists (single rays, spans on 2 threads, packets) equals brute force's bit for
// bit, and kd1's under kd1's own contract with brute force (tests/kdtree/kdtree_test.cpp): the same
// hits and t; at an exact tie in t between triangles of different leaves kd1 keeps the one its
// traversal reaches first instead of the smaller id (rays starting on surfaces, running inside
// planes or along shared edges), so there only t is compared; everywhere else t, u, v bit for bit.
// Adds the number of rays that hit to `hits`.
void expect_kd_answers(const KdTree& kd, const std::vector<SortedLists>& structures, const std::vector<Ray>& rays,
                       const std::string& what, int& hits) {
    const Scene& scene = kd.scene();
    std::vector<Hit> ref(rays.size()), brute(rays.size());
    std::vector<std::uint8_t> ref_occluded(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ref[i] = kd.intersect(rays[i]);
        ref_occluded[i] = kd.occluded(rays[i]) ? 1 : 0;
        brute[i] = intersect_brute_force(scene, rays[i]);
        ASSERT_EQ(ref_occluded[i], occluded_brute_force(scene, rays[i]) ? 1 : 0) << what << ", ray " << i;
        ASSERT_EQ(ref[i].hit(), brute[i].hit()) << what << ", ray " << i;
        ASSERT_EQ(ref[i].t, brute[i].t) << what << ", ray " << i;
    }
    const std::vector<RuleCase> cases = rule_cases();
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const RuleCase& rc = cases[k];
        const SortedLists& lists = structures[k];
        std::vector<Hit> span_hits(rays.size());
        std::vector<std::uint8_t> span_occluded(rays.size(), 7);
        lists.intersect(rays, span_hits, {2, nullptr});
        lists.occluded(rays, span_occluded, {2, nullptr});
        const bool count = k == 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Hit a = lists.intersect(rays[i]);
            const Hit& b = brute[i];
            const std::string where = what + ", " + rc.name + ", ray " + std::to_string(i);
            ASSERT_EQ(a.triangle, b.triangle) << where;
            if (b.hit()) {
                hits += count ? 1 : 0;
                ASSERT_EQ(bits(a.t), bits(b.t)) << where;
                ASSERT_EQ(bits(a.u), bits(b.u)) << where;
                ASSERT_EQ(bits(a.v), bits(b.v)) << where;
            }
            ASSERT_EQ(a.t, ref[i].t) << where << " (kd1)";
            if (ref[i].triangle == b.triangle) {  // kd1 bit for bit
                ASSERT_EQ(bits(a.t), bits(ref[i].t)) << where << " (kd1)";
                ASSERT_EQ(bits(a.u), bits(ref[i].u)) << where << " (kd1)";
                ASSERT_EQ(bits(a.v), bits(ref[i].v)) << where << " (kd1)";
            }
            ASSERT_EQ(lists.occluded(rays[i]) ? 1 : 0, ref_occluded[i]) << where;
            ASSERT_EQ(span_hits[i].triangle, b.triangle) << where << " (span)";
            ASSERT_EQ(bits(span_hits[i].t), bits(b.t)) << where << " (span)";
            ASSERT_EQ(span_occluded[i], ref_occluded[i]) << where << " (span)";
        }
        // Packets: 16 rays each, lanes 2, 5, 8, 11 and 14 inactive.
        const std::size_t packets = rays.size() / 16;
        std::vector<Packet16> ps(packets);
        for (std::size_t p = 0; p < packets; ++p) {
            for (int i = 0; i < 16; ++i) ps[p].set_ray(i, rays[p * 16 + std::size_t(i)]);
            ps[p].active = 0xFFFFu & ~0x4924u;
        }
        std::vector<PacketHits16> ph(packets);
        std::vector<std::uint32_t> po(packets);
        lists.intersect(ps, ph, {2, nullptr});
        lists.occluded(ps, po, {1, nullptr});
        for (std::size_t p = 0; p < packets; ++p)
            for (int i = 0; i < 16; ++i) {
                const bool active = (ps[p].active >> i) & 1u;
                const Hit& b = brute[p * 16 + std::size_t(i)];
                const std::string where =
                    what + ", " + rc.name + ", packet " + std::to_string(p) + " lane " + std::to_string(i);
                ASSERT_EQ(ph[p].triangle[i], active ? b.triangle : kNoHit) << where;
                ASSERT_EQ((po[p] >> i) & 1u, active ? std::uint32_t(ref_occluded[p * 16 + std::size_t(i)]) : 0u)
                    << where;
            }
    }
}

void expect_kd_answers_all_rays(const Scene& scene, const std::string& what, int n, unsigned seed) {
    const KdTree kd = KdTree::build(scene);
    std::vector<SortedLists> structures;
    for (const RuleCase& rc : rule_cases()) structures.push_back(SortedLists::build(scene, rc.rules));
    int hits = 0;
    expect_kd_answers(kd, structures, test::random_rays(scene.bounds(), n, seed), what + " random", hits);
    expect_kd_answers(kd, structures, test::axis_rays(scene, n, seed + 1), what + " axis", hits);
    expect_kd_answers(kd, structures, grazing_rays(scene, n, seed + 2), what + " grazing", hits);
    expect_kd_answers(kd, structures, event_origin_rays(scene, n, seed + 3), what + " event origins", hits);
    expect_kd_answers(kd, structures, test::camera_rays(scene.bounds(), n, seed + 4), what + " camera", hits);
    expect_kd_answers(kd, structures, test::shadow_rays(scene.bounds(), n, seed + 5), what + " shadow", hits);
    EXPECT_GT(hits, n) << what << ": few rays hit anything (a weak test)";
}

}  // namespace

TEST(ListsProperty, RandomSoupEqualsKd1) { expect_kd_answers_all_rays(test::random_soup(400, 1), "soup", 1000, 10); }

TEST(ListsProperty, StackedBoxesEqualKd1) {
    expect_kd_answers_all_rays(test::stacked_boxes(30, 2), "stacked boxes", 1000, 20);
}

TEST(ListsProperty, GridOfQuadsEqualsKd1) { expect_kd_answers_all_rays(test::single_plane(12), "plane", 1000, 30); }

TEST(ListsProperty, TetraEqualsKd1) {
    for (const char* spec : {"tetra:0", "tetra:2", "tetra:4"})
        expect_kd_answers_all_rays(scenes::load_scene(spec).scene, spec, 800, 40);
}

TEST(ListsProperty, CoincidentTrianglesTieToTheSmallerId) {
    // The same quad three times (twice reversed) over a grid: every hit is a tie in t.
    test::Soup s;
    for (int copy = 0; copy < 3; ++copy)
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                const Float3 a{float(i), float(j), 0.0f}, b{float(i + 1), float(j), 0.0f},
                    c{float(i + 1), float(j + 1), 0.0f}, d{float(i), float(j + 1), 0.0f};
                if (copy == 1)
                    s.add_quad(d, c, b, a);
                else
                    s.add_quad(a, b, c, d);
            }
    expect_kd_answers_all_rays(s.scene(), "coincident", 600, 50);
}
