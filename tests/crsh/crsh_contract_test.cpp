// The query contract (query.hpp) as Crsh keeps it: rays that describe no segment report nothing and
// change nobody else's answer, answers do not depend on the input order, bad spans and settings are
// refused, and the counters add up (the paper's metric below brute force on coherent rays).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <limits>
#include <numeric>
#include <random>

#include "beamtrace/crsh.hpp"
#include "beamtrace/error.hpp"
#include "beamtrace/kdtree.hpp"
#include "crsh_test_rays.hpp"
#include "test_scenes.hpp"

using namespace beamtrace;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

std::vector<Ray> invalid_rays() {
    const Float3 o{0.5f, 0.5f, -1.0f}, d{0, 0, 1};
    return {Ray{{kNaN, 0.5f, -1}, 0.0f, d, kInfinity},
            Ray{o, 0.0f, {0, kInfinity, 1}, kInfinity},
            Ray{o, 0.0f, {0, 0, 0}, kInfinity},
            Ray{o, 2.0f, d, 1.0f},
            Ray{o, kNaN, d, kInfinity},
            Ray{o, 0.0f, d, kNaN},
            Ray{o, -kInfinity, d, kInfinity},
            Ray{{kInfinity, 0, 0}, 0.0f, d, kInfinity}};
}

bool same(const Hit& a, const Hit& b) {
    return a.triangle == b.triangle && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
           std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
           std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

}  // namespace

TEST(CrshContract, RaysThatDescribeNoSegmentReportNothingAndDisturbNobody) {
    const Scene scene = test::single_plane(8);  // z = 0.5, x and y in [0, 1]
    const Crsh crsh(scene);
    const std::vector<Ray> valid = test::camera_rays(scene.bounds(), 200, 1);
    std::vector<Hit> alone(valid.size());
    std::vector<std::uint8_t> alone_occluded(valid.size());
    crsh.intersect(valid, alone);
    crsh.occluded(valid, alone_occluded);
    // The invalid rays woven in between the valid ones.
    std::vector<Ray> mixed;
    std::vector<int> where;
    const std::vector<Ray> bad = invalid_rays();
    for (std::size_t i = 0; i < valid.size(); ++i) {
        mixed.push_back(bad[i % bad.size()]);
        where.push_back(-1);
        mixed.push_back(valid[i]);
        where.push_back(int(i));
    }
    for (const CrshKey key : {CrshKey::origin, CrshKey::end_point}) {
        std::vector<Hit> hits(mixed.size());
        std::vector<std::uint8_t> occluded(mixed.size(), 9);
        QueryCounters c;
        crsh.with_key(key).intersect(mixed, hits, {2, &c});
        crsh.with_key(key).occluded(mixed, occluded, {1, nullptr});
        EXPECT_EQ(c.crsh.rays, valid.size());
        for (std::size_t k = 0; k < mixed.size(); ++k) {
            if (where[k] < 0) {
                EXPECT_FALSE(hits[k].hit()) << k;
                EXPECT_EQ(occluded[k], 0) << k;
                EXPECT_FALSE(crsh.intersect(mixed[k]).hit());
                EXPECT_FALSE(crsh.occluded(mixed[k]));
            } else {
                EXPECT_TRUE(same(hits[k], alone[std::size_t(where[k])])) << k;
                EXPECT_EQ(occluded[k], alone_occluded[std::size_t(where[k])]) << k;
            }
        }
    }
    // Only invalid rays, or none at all.
    std::vector<Hit> hits(bad.size());
    crsh.intersect(bad, hits);
    for (const Hit& h : hits) EXPECT_FALSE(h.hit());
    crsh.intersect(std::span<const Ray>(), std::span<Hit>());
}

TEST(CrshContract, AnswersDoNotDependOnTheInputOrder) {
    const Scene scene = test::random_soup(500, 2);
    std::vector<Ray> rays = test::shadow_rays(scene.bounds(), 2000, 3);
    const std::vector<Ray> camera = test::camera_rays(scene.bounds(), 1000, 4);
    rays.insert(rays.end(), camera.begin(), camera.end());
    std::vector<std::size_t> perm(rays.size());
    std::iota(perm.begin(), perm.end(), std::size_t{0});
    std::shuffle(perm.begin(), perm.end(), std::mt19937(5));
    std::vector<Ray> shuffled(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) shuffled[i] = rays[perm[i]];
    CrshSettings rah;
    rah.sort = rah.object_spheres = false;
    for (const CrshSettings& s : {CrshSettings{}, rah}) {
        const Crsh crsh(scene, s);
        std::vector<Hit> a(rays.size()), b(rays.size());
        std::vector<std::uint8_t> oa(rays.size()), ob(rays.size());
        crsh.intersect(rays, a);
        crsh.intersect(shuffled, b, {2, nullptr});
        crsh.occluded(rays, oa);
        crsh.occluded(shuffled, ob);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_TRUE(same(b[i], a[perm[i]])) << i;
            ASSERT_EQ(ob[i], oa[perm[i]]) << i;
        }
    }
}

TEST(CrshContract, RefusesBadSpansAndSettings) {
    const Scene scene = test::random_soup(50, 6);
    const Crsh crsh(scene);
    std::vector<Ray> rays(4);
    std::vector<Hit> hits(3);
    std::vector<std::uint8_t> occluded(5);
    EXPECT_THROW(crsh.intersect(rays, hits), Error);
    EXPECT_THROW(crsh.occluded(rays, occluded), Error);
    std::vector<Hit> four(4);
    EXPECT_THROW(crsh.intersect(rays, four, {0, nullptr}), Error);
    std::vector<Packet16> packets(2);
    std::vector<std::uint32_t> bits(1);
    EXPECT_THROW(crsh.occluded(packets, bits), Error);
    for (auto bad : {+[](CrshSettings& s) { s.fanout = 1; }, +[](CrshSettings& s) { s.fanout = 65; },
                     +[](CrshSettings& s) { s.levels = 0; }, +[](CrshSettings& s) { s.levels = 5; },
                     +[](CrshSettings& s) { s.key_position_bits = 11; }}) {
        CrshSettings s;
        bad(s);
        EXPECT_THROW(s.validate(), Error);
        EXPECT_THROW(Crsh(scene, s), Error);
    }
    std::vector<std::uint32_t> wrong(scene.triangle_count() + 1, 0);
    CrshSettings s;
    s.object_of_triangle = wrong;
    EXPECT_THROW(Crsh(scene, s), Error);
}

TEST(CrshContract, CountersAddUpAndBeatBruteForceOnCoherentRays) {
    const Scene scene = test::stacked_boxes(60, 7);
    std::vector<std::uint32_t> objects(scene.triangle_count());
    for (std::size_t t = 0; t < objects.size(); ++t) objects[t] = std::uint32_t(t / 12);  // each box
    CrshSettings s;
    s.object_of_triangle = objects;
    const Crsh crsh(scene, s);
    EXPECT_EQ(crsh.stats().objects, (objects.size() + 11) / 12);
    EXPECT_EQ(crsh.stats().largest_object, 12u);
    const std::vector<Ray> rays = test::shadow_rays(scene.bounds(), 4096, 8);
    CrshSettings rah_settings;
    rah_settings.sort = rah_settings.object_spheres = false;
    const Crsh rah(scene, rah_settings);
    QueryCounters c, r;
    std::vector<std::uint8_t> o(rays.size());
    crsh.with_key(CrshKey::end_point).occluded(rays, o, {1, &c});
    rah.with_key(CrshKey::end_point).occluded(rays, o, {2, &r});
    EXPECT_EQ(c.crsh.rays, rays.size());
    EXPECT_EQ(c.crsh.nodes[0], rays.size() / 8);
    EXPECT_EQ(c.crsh.nodes[1], rays.size() / 64);
    EXPECT_EQ(c.crsh.object_sphere_tests, (rays.size() / 64) * crsh.stats().objects);
    EXPECT_EQ(r.crsh.object_sphere_tests, 0u);
    EXPECT_EQ(r.crsh.level_tests[1], (rays.size() / 64) * scene.triangle_count());  // RAH: every triangle
    EXPECT_EQ(r.crsh.level_tests[0], r.crsh.level_hits[1] * 8);                     // each child tests its parent's
    for (const QueryCounters* k : {&c, &r}) {
        EXPECT_EQ(k->crsh.sphere_cone_tests, k->crsh.level_tests[0] + k->crsh.level_tests[1]);
        EXPECT_EQ(k->crsh.triangle_tests, k->triangle_tests);
        EXPECT_GT(k->crsh.triangle_tests, 0u);
    }
    const std::uint64_t brute = rays.size() * scene.triangle_count();
    const std::uint64_t crsh_total = c.crsh.object_sphere_tests + c.crsh.sphere_cone_tests + c.crsh.triangle_tests;
    const std::uint64_t rah_total = r.crsh.sphere_cone_tests + r.crsh.triangle_tests;
    EXPECT_LT(crsh_total, rah_total);
    EXPECT_LT(rah_total, brute);
    // The prediction of the top level's work.
    EXPECT_EQ(rah.predicted_top_level_tests(rays.size()), (rays.size() / 64) * scene.triangle_count());
    EXPECT_EQ(crsh.predicted_top_level_tests(rays.size()), (rays.size() / 64) * (crsh.stats().objects + 12));
    EXPECT_EQ(crsh.predicted_top_level_tests(65), 2u * (crsh.stats().objects + 12));
}

TEST(CrshContract, DegenerateTrianglesAreNeverTested) {
    const std::vector<Float3> v{{0, 0, 1}, {1, 0, 1}, {2, 0, 1}, {0, 0, 2}, {1, 0, 2}, {0, 1, 2}};
    const std::vector<std::uint32_t> idx{0, 1, 2, 3, 4, 5};  // a line, then a real triangle
    const Scene scene(v, idx);
    const Crsh crsh(scene);
    EXPECT_EQ(crsh.stats().degenerate_triangles, 1u);
    const Hit h = crsh.intersect(Ray{{0.2f, 0.2f, 0}, 0.0f, {0, 0, 1}, kInfinity});
    EXPECT_EQ(h.triangle, 1u);
    EXPECT_EQ(h.t, 2.0f);
}
