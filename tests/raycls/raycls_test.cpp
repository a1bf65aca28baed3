// RayClassification against brute force, bit for bit: the 5D tree (rays from everywhere, rays along
// axes and in split planes, segments reaching behind their origins), light buffers around a shared
// end point (shadow rays) and a shared start point (camera rays), spans, packets, single rays, two
// threads, the settings' extremes, a budget too small for the cells (rays answered by the kd-tree),
// pruning between calls; and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "beamtrace/error.hpp"
#include "beamtrace/kdtree.hpp"
#include "beamtrace/ray_classification.hpp"
#include "common/triangle_reference.hpp"
#include "test_scenes.hpp"

using namespace beamtrace;

namespace {

// Bit for bit; with `tie` (answers of the kd-tree fallback, which may end in the cell before an
// exact tie's other triangle when the hit lies on a split plane at t = 0 within rounding): the same t,
// and the triangle given is hit there too.
void expect_same_hit(const Hit& got, const Hit& want, std::size_t i, const char* what, const Scene* tie = nullptr,
                     const Ray* ray = nullptr) {
    if (tie && got.triangle != want.triangle && got.hit() && want.hit()) {
        ASSERT_EQ(got.t, want.t) << what << " ray " << i;
        TriangleHit h;
        ASSERT_TRUE(intersect_triangle(make_watertight_ray(*ray), tie->triangle(got.triangle), h) && h.t == got.t)
            << what << " ray " << i;
        return;
    }
    ASSERT_EQ(got.triangle, want.triangle) << what << " ray " << i;
    if (!want.hit()) return;
    ASSERT_EQ(got.t, want.t) << what << " ray " << i;
    ASSERT_EQ(got.u, want.u) << what << " ray " << i;
    ASSERT_EQ(got.v, want.v) << what << " ray " << i;
}

// Span, single-ray and packet answers, closest hit and occlusion, against brute force.
void check_all(const RayClassification& rc, const Scene& scene, const std::vector<Ray>& rays, const char* what,
               int threads = 1, QueryCounters* counters = nullptr) {
    // Exact ties may differ only for rays the kd-tree answers (cells not made yet).
    const Scene* tie = rc.settings().rays_per_new_cell > 1 || rc.settings().entries_per_ray > 0 ? &scene : nullptr;
    std::vector<Hit> hits(rays.size());
    std::vector<std::uint8_t> occ(rays.size());
    rc.intersect(rays, hits, QueryOptions{threads, counters});
    rc.occluded(rays, occ, QueryOptions{threads, counters});
    std::size_t hit_count = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit want = intersect_brute_force(scene, rays[i]);
        hit_count += want.hit();
        expect_same_hit(hits[i], want, i, what, tie, &rays[i]);
        ASSERT_EQ(occ[i] != 0, occluded_brute_force(scene, rays[i])) << what << " occlusion, ray " << i;
        if (i % 7 == 0) {
            expect_same_hit(rc.intersect(rays[i]), want, i, what, tie, &rays[i]);
            ASSERT_EQ(rc.occluded(rays[i]), occ[i] != 0) << what << " single occlusion, ray " << i;
        }
    }
    EXPECT_GT(hit_count, 0u) << what << ": no ray hits anything, the test tests nothing";
    // Packets: every third lane inactive.
    std::vector<Packet16> packets((rays.size() + 15) / 16);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        packets[i / 16].set_ray(int(i % 16), rays[i]);
        if (i % 3 != 2) packets[i / 16].active |= 1u << (i % 16);
    }
    std::vector<PacketHits16> ph(packets.size());
    std::vector<std::uint32_t> po(packets.size());
    rc.intersect(packets, ph, QueryOptions{threads, nullptr});
    rc.occluded(packets, po, QueryOptions{threads, nullptr});
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const bool active = i % 3 != 2;
        const Hit want = active ? hits[i] : Hit{};
        expect_same_hit(ph[i / 16].hit(int(i % 16)), want, i, what, tie, &rays[i]);
        ASSERT_EQ(((po[i / 16] >> (i % 16)) & 1u) != 0, active && occ[i] != 0) << what << " packet lane " << i;
    }
}

// Shadow rays from random points in and around the box towards one light (as the workloads make
// them, tfar just short of 1) and some ending exactly at it.
std::vector<Ray> rays_to_light(const Box& box, Float3 light, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-0.3f, 1.3f);
    const float d = box.diagonal();
    const Float3 e = box.extent() + Float3{0.2f * d, 0.2f * d, 0.2f * d};
    const Float3 lower = box.lower - Float3{0.1f * d, 0.1f * d, 0.1f * d};
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        Ray r;
        r.org = lower + Float3{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z};
        r.dir = light - r.org;
        r.tfar = i % 2 ? 1.0f : 1.0f - 1e-4f;
        rays.push_back(r);
    }
    return rays;
}

// Rays from one point in random directions, each direction twice (closest hit: unbounded; some
// with a finite tfar).
std::vector<Ray> rays_from_point(Float3 eye, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> d(-1.0f, 1.0f), t(0.1f, 2.0f);
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        Ray r;
        r.org = eye;
        if (i % 2) {
            r.dir = rays.back().dir;
        } else {
            do r.dir = Float3{d(rng), d(rng), d(rng)};
            while (dot(r.dir, r.dir) < 1e-4f);
        }
        if (i % 4 == 1) r.tfar = t(rng);
        rays.push_back(r);
    }
    return rays;
}

struct Case {
    const char* name;
    Scene scene;
};

std::vector<Case> scenes() {
    return {{"soup", test::random_soup(3000, 7)},
            {"boxes", test::stacked_boxes(40, 3)},
            {"plane", test::single_plane(24)}};
}

}  // namespace

TEST(RayClassification, SpaceTreeEqualsBruteForce) {
    for (const Case& c : scenes()) {
        RayClsSettings every_cell;
        every_cell.rays_per_new_cell = 1;  // no ray left to the kd-tree: bit for bit, ties included
        every_cell.entries_per_ray = 0;
        const RayClassification rc(c.scene, every_cell);
        std::vector<Ray> rays = test::random_rays(c.scene.bounds(), 3000, 11);
        const std::vector<Ray> axis = test::axis_rays(c.scene, 1500, 12);
        rays.insert(rays.end(), axis.begin(), axis.end());
        for (std::size_t i = 0; i < rays.size(); i += 5) rays[i].tnear = -0.5f;  // reaching behind the origin
        for (std::size_t i = 2; i < rays.size(); i += 5) rays[i].tfar = 0.3f;
        QueryCounters counters;
        check_all(rc, c.scene, rays, c.name, 1, &counters);
        EXPECT_GT(counters.raycls.rays, 0u);
        EXPECT_EQ(counters.raycls.light_buffer_rays, 0u) << "rays from everywhere share no point";
        EXPECT_GT(rc.stats().cells_created, 0u);
        EXPECT_EQ(counters.rays, 0u) << "no ray traced by the kd-tree";
        // The default: cells made once 16 rays reach them, the rays before by the kd-tree.
        const RayClassification lazier(c.scene);
        QueryCounters fallback;
        check_all(lazier, c.scene, rays, c.name, 1, &fallback);
        EXPECT_GT(fallback.rays, 0u);
    }
}

TEST(RayClassification, LightBufferFromSharedEndPoint) {
    for (const Case& c : scenes()) {
        const RayClassification rc(c.scene);
        const Box& b = c.scene.bounds();
        const Float3 e = b.extent();
        const float d = b.diagonal();
        const Float3 light = b.center() + Float3{0.1f * e.x, 0.35f * e.y, -0.05f * e.z + 0.1f * d};
        const std::vector<Ray> rays = rays_to_light(b, light, 4000, 21);
        std::vector<std::uint8_t> occ(rays.size());
        QueryCounters counters;
        rc.occluded(rays, occ, QueryOptions{1, &counters});
        EXPECT_EQ(counters.raycls.light_buffer_rays, counters.raycls.rays) << c.name << ": every ray via the light";
        EXPECT_EQ(rc.stats().light_buffers, 1u);
        std::size_t occluded = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(occ[i] != 0, occluded_brute_force(c.scene, rays[i])) << c.name << " ray " << i;
            occluded += occ[i];
        }
        EXPECT_GT(occluded, 0u);
        EXPECT_LT(occluded, rays.size());
        check_all(rc, c.scene, rays, c.name, 2);
    }
}

TEST(RayClassification, ShadowRaysInRunsOfOneCellAnswerAsOneByOne) {
    // Shadow rays in order of their direction from the light (as neighbouring pixels' are), so that
    // runs of one grid cell form: tested 16 rays a candidate, they answer as brute force does, and as
    // the same rays one by one (packet_light_buffers off).
    for (const Case& c : scenes()) {
        const Box& b = c.scene.bounds();
        const Float3 e = b.extent();
        const Float3 light = b.center() + Float3{0.1f * e.x, 0.45f * e.y, -0.05f * e.z};
        std::vector<Ray> rays = rays_to_light(b, light, 6000, 23);
        std::sort(rays.begin(), rays.end(), [](const Ray& a, const Ray& r) {
            const auto angle = [](const Ray& x) { return std::atan2(x.dir.z, x.dir.x) * 8.0f; };
            const int ka = int(std::floor(angle(a))), kr = int(std::floor(angle(r)));
            if (ka != kr) return ka < kr;
            return a.dir.y / std::sqrt(dot(a.dir, a.dir)) < r.dir.y / std::sqrt(dot(r.dir, r.dir));
        });
        for (bool runs : {true, false}) {
            RayClsSettings s;
            s.packet_light_buffers = runs;
            const RayClassification rc(c.scene, s);
            std::vector<std::uint8_t> occ(rays.size());
            QueryCounters counters;
            rc.occluded(rays, occ, QueryOptions{1, &counters});
            for (std::size_t i = 0; i < rays.size(); ++i)
                ASSERT_EQ(occ[i] != 0, occluded_brute_force(c.scene, rays[i])) << c.name << " runs " << runs << " ray " << i;
            if (runs)
                EXPECT_GT(counters.raycls.run_rays, rays.size() / 4) << c.name;
            else
                EXPECT_EQ(counters.raycls.run_rays, 0u) << c.name;
            check_all(rc, c.scene, rays, c.name, 2);
        }
    }
}

// Shadow rays of each origin towards several lights, interleaved as `--lights N` makes them (ray
// i goes to light i % lights): one light buffer per light up to 16 lights a call, the 5D tree beyond.
TEST(RayClassification, LightBuffersForSeveralLights) {
    for (const Case& c : scenes()) {
        const Box& b = c.scene.bounds();
        const Float3 e = b.extent();
        const float d = b.diagonal();
        for (int lights : {2, 4, 16, 17}) {
            std::vector<std::vector<Ray>> per_light;
            for (int l = 0; l < lights; ++l) {
                const float a = float(l) / float(lights);
                const Float3 light = b.center() + Float3{(a - 0.5f) * e.x, 0.35f * e.y + 0.05f * d, (0.5f - a) * e.z};
                per_light.push_back(rays_to_light(b, light, 3000 / lights + 64, 41 + unsigned(l)));
            }
            std::vector<Ray> rays;
            for (std::size_t i = 0; i < per_light[0].size(); ++i)
                for (int l = 0; l < lights; ++l) rays.push_back(per_light[std::size_t(l)][i]);
            const RayClassification rc(c.scene);
            std::vector<std::uint8_t> occ(rays.size());
            QueryCounters counters;
            rc.occluded(rays, occ, QueryOptions{1, &counters});
            const std::string what = std::string(c.name) + ", " + std::to_string(lights) + " lights";
            if (lights <= 16) {
                EXPECT_EQ(counters.raycls.light_buffer_rays, counters.raycls.rays) << what << ": every ray via its light";
                EXPECT_EQ(rc.stats().light_buffers, std::size_t(lights)) << what;
                // A last cell per light: interleaving the lights finds about as many rays in the last
                // cell of their light as the same rays light by light do.
                std::vector<Ray> grouped;
                for (const std::vector<Ray>& l : per_light) grouped.insert(grouped.end(), l.begin(), l.end());
                const RayClassification again(c.scene);
                std::vector<std::uint8_t> grouped_occ(grouped.size());
                QueryCounters grouped_counters;
                again.occluded(grouped, grouped_occ, QueryOptions{1, &grouped_counters});
                EXPECT_GT(grouped_counters.raycls.cache_hits, 0u) << what;
                EXPECT_GE(double(counters.raycls.cache_hits), 0.8 * double(grouped_counters.raycls.cache_hits)) << what;
            } else {
                EXPECT_EQ(counters.raycls.light_buffer_rays, 0u) << what << ": more points than a call takes";
                EXPECT_EQ(rc.stats().light_buffers, 0u) << what;
            }
            std::size_t occluded = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                ASSERT_EQ(occ[i] != 0, occluded_brute_force(c.scene, rays[i])) << what << " ray " << i;
                occluded += occ[i];
            }
            EXPECT_GT(occluded, 0u) << what;
            EXPECT_LT(occluded, rays.size()) << what;
            if (lights == 4) check_all(rc, c.scene, rays, what.c_str(), 2);
        }
    }
}

TEST(RayClassification, LightBufferFromSharedStartPoint) {
    for (const Case& c : scenes()) {
        const RayClassification rc(c.scene);
        const Box& b = c.scene.bounds();
        const Float3 e = b.extent();
        const std::vector<Ray> rays = rays_from_point(b.center() + Float3{0.05f * e.x, 0.1f * e.y, 0.2f * e.z}, 4000, 31);
        QueryCounters counters;
        std::vector<Hit> hits(rays.size());
        rc.intersect(rays, hits, QueryOptions{1, &counters});
        EXPECT_EQ(counters.raycls.light_buffer_rays, counters.raycls.rays) << c.name;
        EXPECT_GT(counters.raycls.cache_hits, 0u);
        check_all(rc, c.scene, rays, c.name);
        // A light buffer with one cell per face and one with deep cells: the same answers.
        for (int depth : {1, 12}) {
            RayClsSettings s;
            s.light_buffer_max_depth = depth;
            s.min_candidates = 0;
            check_all(RayClassification(c.scene, s), c.scene, rays, c.name);
        }
    }
}

TEST(RayClassification, SettingsDoNotChangeAnswers) {
    const Scene scene = test::stacked_boxes(30, 5);
    std::vector<Ray> rays = test::random_rays(scene.bounds(), 2000, 41);
    const std::vector<Ray> shadow = rays_to_light(scene.bounds(), scene.bounds().center(), 1000, 42);
    rays.insert(rays.end(), shadow.begin(), shadow.end());
    for (int depth : {1, 2, 8}) {
        for (bool cache : {false, true}) {
            RayClsSettings s;
            s.max_depth = depth;
            s.cache = cache;
            s.rays_per_new_cell = cache ? 1 : 16;
            s.light_buffers = depth != 2;
            s.min_candidates = depth == 8 ? 0 : 6;
            check_all(RayClassification(scene, s), scene, rays, "settings");
        }
    }
}

TEST(RayClassification, BudgetTooSmallFallsBackToTheTreeAndPrunes) {
    const Scene scene = test::random_soup(4000, 9);
    RayClsSettings s;
    s.memory_budget_bytes = 64 * 1024;  // a few cells
    s.rays_per_new_cell = 1;
    s.entries_per_ray = 0;
    const RayClassification rc(scene, s);
    const std::vector<Ray> rays = test::random_rays(scene.bounds(), 3000, 51);
    for (int call = 0; call < 3; ++call) {
        std::vector<Hit> hits(rays.size());
        QueryCounters counters;
        rc.intersect(rays, hits, QueryOptions{1, &counters});
        EXPECT_GT(counters.rays, 0u) << "call " << call << ": some rays must have been traced by the kd-tree";
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Hit want = intersect_brute_force(scene, rays[i]);
            // The kd-tree may pick another triangle of an exact tie: the same t, a real hit of its triangle.
            ASSERT_EQ(hits[i].hit(), want.hit()) << "ray " << i;
            if (want.hit()) {
                ASSERT_EQ(hits[i].t, want.t) << "ray " << i;
            }
        }
    }
    const RayClsStats st = rc.stats();
    EXPECT_GT(st.cells_freed, 0u) << "calls over the budget free old cells";
    EXPECT_LE(st.memory_peak_bytes, s.memory_budget_bytes) << "a cell that does not fit is dropped";
}

TEST(RayClassification, LightBuffersKeepToTheBudget) {
    // Sixteen lights' buffers under a budget smaller than one light's tiles: a tile that does not fit
    // is dropped (its rays go to the kd-tree), so the cells never hold more than the budget, and the
    // next call frees old cells to make room.
    const Scene scene = test::random_soup(6000, 13);
    const Box& b = scene.bounds();
    const Float3 e = b.extent();
    RayClsSettings s;
    s.memory_budget_bytes = 96 * 1024;
    std::vector<Ray> rays;
    for (int l = 0; l < 16; ++l) {
        const float a = float(l) / 16.0f;
        const Float3 light = b.center() + Float3{(a - 0.5f) * e.x, 0.45f * e.y, (0.5f - a) * e.z};
        const std::vector<Ray> to = rays_to_light(b, light, 400, 91 + unsigned(l));
        rays.insert(rays.end(), to.begin(), to.end());
    }
    const RayClassification rc(scene, s);
    std::uint64_t from_buffers = 0;
    for (int call = 0; call < 3; ++call) {
        std::vector<std::uint8_t> occ(rays.size());
        QueryCounters counters;
        rc.occluded(rays, occ, QueryOptions{1, &counters});
        from_buffers += counters.raycls.light_buffer_rays;
        for (std::size_t i = 0; i < rays.size(); ++i)
            ASSERT_EQ(occ[i] != 0, occluded_brute_force(scene, rays[i])) << "call " << call << " ray " << i;
        EXPECT_LE(rc.stats().memory_peak_bytes, s.memory_budget_bytes) << "call " << call;
    }
    EXPECT_GT(from_buffers, 0u) << "some tiles fit";
}

TEST(RayClassification, WorkCapLeavesRaysToTheTree) {
    const Scene scene = test::random_soup(3000, 4);
    RayClsSettings s;
    s.entries_per_ray = 1;  // far fewer entries than the cells need
    s.rays_per_new_cell = 1;
    const RayClassification rc(scene, s);
    const std::vector<Ray> rays = test::random_rays(scene.bounds(), 2000, 71);
    QueryCounters counters;
    check_all(rc, scene, rays, "capped", 1, &counters);
    EXPECT_GT(counters.rays, 0u) << "rays traced by the kd-tree once the cap is reached";
    EXPECT_GT(rc.stats().cells_created, 0u);
}

// Incoherent rays (random origins and directions) rarely reach a made cell: after a window of 4,096
// rays mostly traced by the kd-tree, the call makes no more cells; the answers do not change.
TEST(RayClassification, IncoherentCallsStopMakingCells) {
    const Scene scene = test::random_soup(3000, 9);
    RayClsSettings s;
    s.entries_per_ray = 0;  // no work cap: only the payoff check stops the build
    s.rays_per_new_cell = 64;
    const RayClassification rc(scene, s);
    const std::vector<Ray> rays = test::random_rays(scene.bounds(), 70000, 81);
    std::vector<Hit> hits(rays.size());
    rc.intersect(rays, hits);
    EXPECT_GE(rc.stats().growth_stops, 1u);
    const std::uint64_t cells = rc.stats().cells_created;
    for (std::size_t i = 0; i < rays.size(); i += 5)
        expect_same_hit(hits[i], intersect_brute_force(scene, rays[i]), i, "incoherent", &scene, &rays[i]);
    // The next call starts growing again (and stops again), on two threads too (the windows are
    // counted per thread across the call's chunks).
    rc.intersect(rays, hits);
    EXPECT_GE(rc.stats().growth_stops, 2u);
    EXPECT_GE(rc.stats().cells_created, cells);
    rc.intersect(rays, hits, QueryOptions{2, nullptr});
    EXPECT_GE(rc.stats().growth_stops, 3u);
    for (std::size_t i = 3; i < rays.size(); i += 5)
        expect_same_hit(hits[i], intersect_brute_force(scene, rays[i]), i, "incoherent, 2 threads", &scene, &rays[i]);
}

TEST(RayClassification, ClearForgetsCellsAndKeepsAnswers) {
    const Scene scene = test::random_soup(2000, 3);
    const RayClassification rc(scene);
    const std::vector<Ray> rays = test::random_rays(scene.bounds(), 1000, 61);
    std::vector<Hit> a(rays.size()), b(rays.size());
    rc.intersect(rays, a);
    EXPECT_GT(rc.stats().memory_bytes, 0u);
    const std::size_t roots = [&] {
        rc.clear();
        return rc.stats().memory_bytes;
    }();
    EXPECT_EQ(rc.stats().cells_created, 0u);
    rc.intersect(rays, b);
    EXPECT_GT(rc.stats().memory_bytes, roots);
    for (std::size_t i = 0; i < rays.size(); ++i) expect_same_hit(b[i], a[i], i, "after clear");
}

TEST(RayClassification, RaysThatDescribeNoSegmentNeverHit) {
    const Scene scene = test::random_soup(500, 1);
    const RayClassification rc(scene);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const Float3 c = scene.bounds().center();
    std::vector<Ray> rays = {Ray{c, 0.0f, {0, 0, 0}, kInfinity},   Ray{c, 0.0f, {nan, 1, 0}, kInfinity},
                             Ray{c, 2.0f, {1, 0, 0}, 1.0f},        Ray{{kInfinity, 0, 0}, 0.0f, {1, 0, 0}, 1.0f},
                             Ray{c, nan, {0, 1, 0}, kInfinity},    Ray{c, 0.0f, {0, 0, 1}, nan}};
    std::vector<Hit> hits(rays.size());
    std::vector<std::uint8_t> occ(rays.size());
    rc.intersect(rays, hits);
    rc.occluded(rays, occ);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        EXPECT_FALSE(hits[i].hit()) << i;
        EXPECT_EQ(occ[i], 0) << i;
        EXPECT_FALSE(rc.intersect(rays[i]).hit()) << i;
    }
}

TEST(RayClassification, BadInputIsRejectedWithAMessage) {
    const Scene scene = test::random_soup(100, 1);
    for (int which = 0; which < 6; ++which) {
        RayClsSettings s;
        if (which == 0) s.max_depth = -1;
        if (which == 1) s.max_depth = 13;
        if (which == 2) s.light_buffer_max_depth = 21;
        if (which == 3) s.min_candidates = -2;
        if (which == 4) s.rays_per_new_cell = 0;
        if (which == 5) s.entries_per_ray = -1;
        EXPECT_THROW(s.validate(), Error);
        EXPECT_THROW(RayClassification(scene, s), Error);
    }
    const RayClassification rc(scene);
    std::vector<Ray> rays(4);
    std::vector<Hit> hits(3);
    try {
        rc.intersect(rays, hits);
        FAIL() << "spans of different sizes were accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("4 inputs"), std::string::npos) << e.what();
    }
    std::vector<std::uint8_t> occ(4);
    EXPECT_THROW(rc.occluded(rays, occ, QueryOptions{0, nullptr}), Error);
}
