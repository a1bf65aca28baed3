// VisibilityField queries against the brute-force reference. Both use the same watertight triangle
// test, so closest hits of mode exact have bit-identical t (the triangle may differ only at a tie),
// and occlusion answers are equal. Packets answer exactly as single rays. Mode fast never invents
// a hit: it can only miss one, and its miss rate is recorded.
#include <gtest/gtest.h>

#include <bit>
#include <random>

#include "../kdtree/test_scenes.hpp"
#include "beamtrace/error.hpp"
#include "beamtrace/kdtree.hpp"
#include "beamtrace/vlf.hpp"

using namespace beamtrace;

namespace {

void expect_same_hit(const Hit& a, const Hit& b, std::size_t i) {
    ASSERT_EQ(a.hit(), b.hit()) << "ray " << i;
    if (!a.hit()) return;
    ASSERT_EQ(a.t, b.t) << "ray " << i;  // another triangle only at a tie
    if (a.triangle == b.triangle) {
        ASSERT_EQ(std::bit_cast<std::uint32_t>(a.t), std::bit_cast<std::uint32_t>(b.t)) << "ray " << i;
        ASSERT_EQ(a.u, b.u) << "ray " << i;
        ASSERT_EQ(a.v, b.v) << "ray " << i;
    }
}

// Exact mode equals brute force on every ray; returns the number of hits.
int expect_exact(const VisibilityField& field, const Scene& scene, const std::vector<Ray>& rays) {
    int hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit a = field.intersect(rays[i]), b = intersect_brute_force(scene, rays[i]);
        expect_same_hit(a, b, i);
        if (::testing::Test::HasFatalFailure()) return hits;
        hits += a.hit();
        EXPECT_EQ(field.occluded(rays[i]), occluded_brute_force(scene, rays[i])) << "ray " << i;
    }
    return hits;
}

// Rays along the set's own directions (and their opposites), from points in and around the box.
std::vector<Ray> beam_rays(const DirectionSet& set, const Box& box, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-0.2f, 1.2f);
    std::vector<Ray> rays;
    for (int k = 0; k < n; ++k) {
        Ray r;
        const Float3 e = box.extent();
        r.org = box.lower + Float3{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z};
        r.dir = set.direction(int(rng() % std::uint32_t(set.size()))) * ((k & 1) ? -1.0f : 1.0f);
        r.tfar = (k % 3 == 0) ? 0.1f * box.diagonal() : kInfinity;
        rays.push_back(r);
    }
    return rays;
}

VlfOptions opts(int l, int n, int d, bool eager = false) {
    VlfOptions o;
    o.directions = l;
    o.tiles = n;
    o.depth = d;
    o.eager = eager;
    return o;
}

struct Settings {
    int directions, tiles, depth;
};

}  // namespace

TEST(VlfOptions, Validation) {
    const Scene s = test::random_soup(10, 1);
    EXPECT_THROW(VisibilityField(s, opts(100, 128, 4)), Error);
    EXPECT_THROW(VisibilityField(s, opts(513, 0, 4)), Error);
    EXPECT_THROW(VisibilityField(s, opts(513, 128, -1)), Error);
    EXPECT_THROW(VisibilityField(s, opts(513, 128, 17)), Error);
    VlfOptions small;
    small.bounds = Box{{0.4f, 0.4f, 0.4f}, {0.5f, 0.5f, 0.5f}};
    EXPECT_THROW(VisibilityField(s, small), Error);  // does not hold the scene
    EXPECT_NO_THROW(VisibilityField(s, opts(9, 1, 0)));
}

// Tile entries keep 3-byte ids (kernels/vlf/build/packed_ids.hpp): a field refuses a scene of more
// than 2^24 triangles with an error that says so, before it allocates anything for them.
TEST(VisibilityField, RefusesMoreTrianglesThanItsIdsHold) {
    const std::vector<Float3> vertices{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    std::vector<std::uint32_t> indices(3 * ((std::size_t(1) << 24) + 1));
    for (std::size_t k = 0; k < indices.size(); ++k) indices[k] = std::uint32_t(k % 3);
    const Scene scene(vertices, indices);
    indices = {};
    try {
        VisibilityField field(scene, VlfOptions{});
        FAIL() << "a field of 2^24 + 1 triangles was built";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("at most 16777216 triangles"), std::string::npos) << e.what();
    }
}

TEST(VisibilityField, RandomSoupEqualsBruteForce) {
    const Scene s = test::random_soup(2000, 11);
    for (Settings st :
         {Settings{9, 1, 0}, Settings{9, 16, 2}, Settings{33, 64, 4}, Settings{129, 128, 6}, Settings{33, 7, 16}}) {
        SCOPED_TRACE(testing::Message() << "l " << st.directions << " n " << st.tiles << " d " << st.depth);
        const VisibilityField field(s, opts(st.directions, st.tiles, st.depth));
        EXPECT_GT(expect_exact(field, s, test::random_rays(s.bounds(), 6000, 12)), 500);
        if (HasFatalFailure()) return;
        EXPECT_GT(expect_exact(field, s, beam_rays(field.directions(), s.bounds(), 3000, 13)), 100);
        if (HasFatalFailure()) return;
        expect_exact(field, s, test::axis_rays(s, 3000, 14));
        if (HasFatalFailure()) return;
    }
}

TEST(VisibilityField, BigTrianglesAndClosedBoxesEqualBruteForce) {
    // Big soup triangles span many tiles and straddle many leaves; boxes give shared edges,
    // coplanar faces and rays from inside a closed room.
    const Scene soup = test::random_soup(300, 21, 0.8f);
    const VisibilityField a(soup, opts(33, 32, 4));
    EXPECT_GT(expect_exact(a, soup, test::random_rays(soup.bounds(), 10000, 22)), 1000);
    const Scene boxes = test::stacked_boxes(120, 23);
    const VisibilityField b(boxes, opts(129, 64, 4));
    EXPECT_GT(expect_exact(b, boxes, test::random_rays(boxes.bounds(), 10000, 24)), 1000);
    expect_exact(b, boxes, test::axis_rays(boxes, 10000, 25));
    expect_exact(b, boxes, beam_rays(b.directions(), boxes.bounds(), 5000, 26));
    const Scene plane = test::single_plane(30);
    const VisibilityField c(plane, opts(9, 16, 3));
    expect_exact(c, plane, test::random_rays(plane.bounds(), 5000, 27));
    expect_exact(c, plane, test::axis_rays(plane, 5000, 28));
}

TEST(VisibilityField, PacketsAnswerAsSingleRays) {
    const Scene s = test::random_soup(3000, 31);
    const VisibilityField field(s, opts(129, 64, 4));
    std::vector<Ray> rays = test::random_rays(s.bounds(), 8000, 32);
    const std::vector<Ray> more = beam_rays(field.directions(), s.bounds(), 8000, 33);
    rays.insert(rays.end(), more.begin(), more.end());
    for (VlfMode mode : {VlfMode::exact, VlfMode::fast}) {
        for (std::size_t b = 0; b + 16 <= rays.size(); b += 16) {
            Packet16 p;
            for (int i = 0; i < 16; ++i) p.set_ray(i, rays[b + std::size_t(i)]);
            p.active = 0xFFFFu & ~(1u << (b / 16 % 16));  // one lane idle
            PacketHits16 hits;
            field.intersect(p, hits, mode);
            const std::uint32_t occluded = field.occluded(p, mode);
            for (int i = 0; i < 16; ++i) {
                const bool active = (p.active >> i) & 1u;
                const Hit single = active ? field.intersect(p.ray(i), mode) : Hit{};
                const Hit packed = hits.hit(i);
                ASSERT_EQ(packed.triangle, single.triangle) << b + std::size_t(i);
                ASSERT_EQ(std::bit_cast<std::uint32_t>(packed.t), std::bit_cast<std::uint32_t>(single.t));
                ASSERT_EQ((occluded >> i) & 1u, active ? std::uint32_t(field.occluded(p.ray(i), mode)) : 0u);
            }
        }
    }
}

TEST(VisibilityField, FastModeOnlyMissesAndItsRateIsRecorded) {
    const Scene s = test::random_soup(3000, 41);
    const VisibilityField field(s, opts(129, 64, 4));
    const std::vector<Ray> rays = test::random_rays(s.bounds(), 20000, 42);
    int differ = 0, occlusion_differ = 0, hits = 0;
    for (const Ray& r : rays) {
        const Hit exact = field.intersect(r), fast = field.intersect(r, VlfMode::fast);
        hits += exact.hit();
        if (fast.hit()) {  // a real hit of the ray, never nearer than the closest one
            ASSERT_TRUE(exact.hit());
            ASSERT_GE(fast.t, exact.t);
            ASSERT_GE(fast.t, r.tnear);
            ASSERT_LE(fast.t, r.tfar);
        }
        differ += fast.triangle != exact.triangle || fast.t != exact.t;
        const bool o_exact = field.occluded(r), o_fast = field.occluded(r, VlfMode::fast);
        ASSERT_TRUE(!o_fast || o_exact);
        occlusion_differ += o_fast != o_exact;
    }
    // Random rays cross many tiles, so fast mode misses often; the rate is the measurement.
    RecordProperty("fast_closest_hit_disagreement", std::to_string(double(differ) / double(rays.size())));
    RecordProperty("fast_occlusion_disagreement", std::to_string(double(occlusion_differ) / double(rays.size())));
    EXPECT_GT(hits, 1000);
    EXPECT_GT(differ, 0) << "random rays cross tiles: fast mode must miss some hits";
    EXPECT_LT(differ, hits);
}

TEST(VisibilityField, BuildsOnlyWhatQueriesNeed) {
    const Scene s = test::random_soup(500, 51);
    VisibilityField field(s, opts(33, 32, 2));
    EXPECT_EQ(field.stats().psfs_built, 0u);
    Ray r;
    r.org = s.bounds().center() - Float3{0, 0, 2};
    r.dir = {0, 0, 1};
    field.intersect(r);
    EXPECT_EQ(field.stats().psfs_built, 1u);
    field.intersect(Ray{r.org, 0.0f, {0, 0, -1}, kInfinity});  // the same line: the same PSF
    EXPECT_EQ(field.stats().psfs_built, 1u);
    EXPECT_GT(field.stats().tile_entries, 0u);
    EXPECT_GT(field.stats().memory_bytes, 0u);
    double last = 0.0;
    field.build_all([&](double f) {
        EXPECT_GE(f, last);
        last = f;
    });
    EXPECT_EQ(last, 1.0);
    const VlfStats st = field.stats();
    EXPECT_EQ(st.psfs_built, 33u);
    EXPECT_GT(st.build_seconds, 0.0);
    const VisibilityField eager(s, opts(33, 32, 2, true));
    EXPECT_EQ(eager.stats().psfs_built, 33u);
    EXPECT_EQ(eager.stats().tile_entries, st.tile_entries);
}

TEST(VisibilityField, BinnedStreamsAnswerAsPackets) {
    const Scene s = test::random_soup(2000, 71);
    const VisibilityField field(s, opts(33, 48, 4));
    std::vector<Ray> rays = test::random_rays(s.bounds(), 4000, 72);
    const std::vector<Ray> more = beam_rays(field.directions(), s.bounds(), 4000, 73);
    rays.insert(rays.end(), more.begin(), more.end());
    std::vector<Packet16> packets(rays.size() / 16);
    for (std::size_t p = 0; p < packets.size(); ++p) {
        for (int i = 0; i < 16; ++i) packets[p].set_ray(i, rays[p * 16 + std::size_t(i)]);
        packets[p].active = p % 7 == 0 ? 0x0F0Fu : 0xFFFFu;
    }
    for (VlfMode mode : {VlfMode::exact, VlfMode::fast}) {
        std::vector<PacketHits16> hits(packets.size());
        std::vector<std::uint32_t> occluded(packets.size());
        field.intersect(packets, hits, mode);
        field.occluded(packets, occluded, mode);
        std::size_t hit_count = 0;
        for (std::size_t p = 0; p < packets.size(); ++p) {
            PacketHits16 one;
            field.intersect(packets[p], one, mode);
            ASSERT_EQ(occluded[p], field.occluded(packets[p], mode)) << p;
            for (int i = 0; i < 16; ++i) {
                ASSERT_EQ(hits[p].triangle[i], one.triangle[i]) << p << " " << i;
                ASSERT_EQ(std::bit_cast<std::uint32_t>(hits[p].t[i]), std::bit_cast<std::uint32_t>(one.t[i]));
                hit_count += one.triangle[i] != kNoHit;
            }
        }
        EXPECT_GT(hit_count, 1000u);
    }
}

// Streams with many rays per PSF: the one-tile rays are binned by PSF and by blocks of tiles (here
// l = 9 and 48,000 rays, about 5,300 a PSF: blocks of 16 x 16 tiles, each bin several chunks, the
// newest partly filled). Every packet answers as when traced alone, in both modes.
TEST(VisibilityField, BinnedStreamsInBlocksOfTilesAnswerAsPackets) {
    const Scene s = test::random_soup(3000, 74);
    const VisibilityField field(s, opts(9, 48, 4));
    const std::vector<Ray> rays = beam_rays(field.directions(), s.bounds(), 48000, 75);
    std::vector<Packet16> packets(rays.size() / 16);
    for (std::size_t p = 0; p < packets.size(); ++p) {
        for (int i = 0; i < 16; ++i) packets[p].set_ray(i, rays[p * 16 + std::size_t(i)]);
        packets[p].active = p % 5 == 0 ? 0x7FFEu : 0xFFFFu;
    }
    for (VlfMode mode : {VlfMode::exact, VlfMode::fast}) {
        std::vector<std::uint32_t> occluded(packets.size());
        field.occluded(packets, occluded, mode);
        std::size_t count = 0;
        for (std::size_t p = 0; p < packets.size(); ++p) {
            ASSERT_EQ(occluded[p], field.occluded(packets[p], mode)) << p;
            count += std::size_t(__builtin_popcount(occluded[p]));
        }
        EXPECT_GT(count, 5000u);
        EXPECT_LT(count, rays.size() - 5000u);
    }
}
