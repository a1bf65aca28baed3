// The leaf kernels of VLF-RT against their scalar references on every instruction set this CPU
// has: the entry occlusion and the closest hit among a leaf's entries (entry_occlusion.hpp,
// entry_closest_hit.hpp), and the packed ids their blocks hold (packed_ids.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "../kdtree/test_scenes.hpp"
#include "common/triangle_reference.hpp"
#include "vlf/query/entry_occlusion.hpp"
#include "vlf/query/tile_footprint.hpp"
#include "vlf/vlf_kernels.hpp"
#include "vlf_kernel_test_support.hpp"

using namespace beamtrace;
using namespace beamtrace::vlf;
using namespace beamtrace::vlf::test_support;

// Packed ids (packed_ids.hpp) read back as they were written, every bit of 24, at every offset of
// an exactly sized buffer (the sanitizer build catches a read past it), and the padding is zero.
TEST(PackedIds, ReadBackWhatWasPacked) {
    std::mt19937 rng(7);
    for (std::size_t n : {1u, 2u, 3u, 4u, 5u, 15u, 16u, 17u, 100u, 1001u}) {
        std::vector<std::uint32_t> ids(n);
        for (std::size_t k = 0; k < n; ++k)
            ids[k] = k % 3 == 0 ? std::uint32_t(kMaxFieldTriangles - 1 - k) : std::uint32_t(rng() % kMaxFieldTriangles);
        const std::vector<std::uint32_t> words = packed(ids);
        ASSERT_EQ(words.size() * 4, ((3 * n + 1) + 3) / 4 * 4);
        const PackedIds p = view(words);
        for (std::size_t k = 0; k < n; ++k) {
            ASSERT_EQ(p[k], ids[k]) << "n " << n << " k " << k;
            ASSERT_EQ((p + k)[0], ids[k]);
        }
        for (std::size_t b = 3 * n; b < 4 * words.size(); ++b) ASSERT_EQ(p.bytes[b], 0u);
    }
}

// The entry occlusion (entry_occlusion.hpp) of every instruction set against its scalar reference:
// runs of tile entries taken from real tiles of a field, rays of every kind and footprints that let
// few, many or more than kEntryCandidates entries pass, with and without repeated ids.
TEST(VlfKernels, EntryOcclusionEqualsScalar) {
    const Scene scene = test::random_soup(400, 94, 0.5f);  // big triangles: many rays hit some
    const std::span<const Triangle> tris = scene.triangles();
    std::mt19937 rng(95);
    const std::vector<Ray> rays = test::random_rays(scene.bounds(), 3000, 96);
    const OccludeEntriesFn scalar = vlf_kernels(Isa::scalar).occlude_entries;
    std::size_t hits = 0, clear = 0, too_many = 0;
    for (Isa isa : simd_isas()) {
        SCOPED_TRACE(isa_name(isa));
        const OccludeEntriesFn simd = vlf_kernels(isa).occlude_entries;
        for (std::size_t trial = 0; trial < rays.size(); ++trial) {
            const WatertightRay ray = make_watertight_ray(rays[trial]);
            const std::uint32_t count = std::uint32_t(rng() % 60);
            const bool distinct = trial % 2 == 0;
            std::vector<std::uint32_t> ids(count), footprints(count);
            for (std::uint32_t k = 0; k < count; ++k) {
                ids[k] = distinct ? std::uint32_t((trial * 7 + k * 13) % tris.size())  // distinct: count < 400 / 13
                                  : std::uint32_t(rng() % 24);                         // repeats likely
                footprints[k] = random_triangle_footprint(rng);
            }
            const std::uint32_t fp = random_ray_footprint(rng, 40);
            std::uint32_t a = kNoHit, b = kNoHit;
            const std::vector<std::uint32_t> words = packed(ids);
            const EntriesAnswer ea = scalar(ray, tris.data(), footprints.data(), view(words), count, fp, distinct, &a);
            const EntriesAnswer eb = simd(ray, tris.data(), footprints.data(), view(words), count, fp, distinct, &b);
            ASSERT_EQ(int(ea), int(eb)) << "trial " << trial;
            if (ea == EntriesAnswer::hit) {
                ASSERT_EQ(a, b) << "trial " << trial;
            }
            hits += ea == EntriesAnswer::hit;
            clear += ea == EntriesAnswer::clear;
            too_many += ea == EntriesAnswer::too_many;
        }
    }
    if (simd_isas().empty()) GTEST_SKIP() << "no SIMD instruction set on this CPU";
    EXPECT_GT(hits, 100u);
    EXPECT_GT(clear, 100u);
    EXPECT_GT(too_many, 10u);
}

// The reference itself against brute force: occluded exactly when one of the passing triangles is
// hit, never two tests of one id.
TEST(VlfKernels, EntryOcclusionReferenceIsTheFootprintFilteredAnyHit) {
    const Scene scene = test::random_soup(200, 97, 0.5f);
    const std::span<const Triangle> tris = scene.triangles();
    std::mt19937 rng(98);
    const std::vector<Ray> rays = test::random_rays(scene.bounds(), 5000, 99);
    std::size_t hits = 0;
    for (const Ray& r : rays) {
        const WatertightRay ray = make_watertight_ray(r);
        const std::uint32_t count = 1 + std::uint32_t(rng() % 30);
        std::vector<std::uint32_t> ids(count), footprints(count, 0u);  // word 0: a box over the whole tile
        for (std::uint32_t k = 0; k < count; ++k) ids[k] = std::uint32_t(rng() % tris.size());
        std::uint32_t hit = kNoHit;
        const EntriesAnswer a = occlude_entries_scalar(ray, tris.data(), footprints.data(), view(packed(ids)), count,
                                                       0xFFFFFFFFu, false, &hit);
        std::vector<std::uint32_t> distinct;
        bool expected = false;
        std::uint32_t first = kNoHit;
        for (std::uint32_t id : ids) {
            if (std::find(distinct.begin(), distinct.end(), id) != distinct.end()) continue;
            distinct.push_back(id);
            TriangleHit h;
            if (!expected && intersect_triangle(ray, tris[id], h)) {
                expected = true;
                first = id;
            }
        }
        if (distinct.size() > kEntryCandidates) {
            ASSERT_EQ(int(a), int(EntriesAnswer::too_many));
            continue;
        }
        ASSERT_EQ(a == EntriesAnswer::hit, expected);
        if (expected) {
            ASSERT_EQ(hit, first);
        }
        hits += expected;
    }
    EXPECT_GT(hits, 50u);
}

// The closest hit among a leaf's entries (entry_closest_hit.hpp) of every instruction set that has
// it against the scalar reference: the same decision, the same best hit bit for bit, the same
// tested list; entries with ids already tested, lists near their room, more candidates than the
// kernel takes.
TEST(VlfKernels, EntryClosestHitEqualsScalar) {
    const Scene scene = test::random_soup(400, 101, 0.5f);
    const std::span<const Triangle> tris = scene.triangles();
    std::mt19937 rng(102);
    const std::vector<Ray> rays = test::random_rays(scene.bounds(), 10000, 103);
    std::size_t improved = 0, undecided = 0, skipped_tested = 0, compared = 0;
    std::vector<std::uint32_t> order(tris.size());  // the caller's ids: ties in t go to the smaller
    for (std::uint32_t k = 0; k < order.size(); ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), rng);
    for (Isa isa : simd_isas()) {
        const ClosestEntriesFn simd = vlf_kernels(isa).closest_entries;
        if (simd == nullptr) continue;
        SCOPED_TRACE(isa_name(isa));
        for (std::size_t trial = 0; trial < rays.size(); ++trial) {
            WatertightRay ray = make_watertight_ray(rays[trial]);
            const std::uint32_t count = std::uint32_t(rng() % 40);
            std::vector<std::uint32_t> ids(count), footprints(count);
            const std::uint32_t start = std::uint32_t(rng() % tris.size());
            for (std::uint32_t k = 0; k < count; ++k) {  // distinct ids, as in one leaf
                ids[k] = (start + k * 7) % std::uint32_t(tris.size());
                footprints[k] = random_triangle_footprint(rng);
            }
            const std::uint32_t fp = random_ray_footprint(rng, 60);
            // A tested list holding some of these ids (and others), sometimes nearly full.
            std::uint32_t list_a[32 + 16], list_b[32 + 16];  // + 16: TestedIds
            const std::uint32_t room = 32, listed = std::uint32_t(rng() % (trial % 5 == 0 ? 32 : 6));
            for (std::uint32_t k = 0; k < listed; ++k)
                list_a[k] = list_b[k] =
                    (count > 0 && k % 2 == 0) ? ids[rng() % count] : std::uint32_t(rng() % tris.size());
            Hit best_a, best_b;
            if (trial % 4 == 0) {  // a hit found earlier: only nearer ones may replace it
                TriangleHit h;
                for (std::uint32_t t = 0; t < tris.size(); ++t)
                    if (intersect_triangle(ray, tris[t], h) && h.t < best_a.t) best_a = Hit{h.t, t, h.u, h.v};
                if (best_a.hit()) best_a.t *= 1.5f;
                best_b = best_a;
                if (best_a.hit()) ray.tfar = best_a.t;
            }
            const std::uint32_t before = best_a.triangle;
            TestedIds ta{list_a, listed, room}, tb{list_b, listed, room};
            const std::vector<std::uint32_t> words = packed(ids);
            const bool da = closest_entries_scalar(ray, tris.data(), order.data(), footprints.data(), view(words),
                                                   count, fp, ta, best_a);
            const bool db = simd(ray, tris.data(), order.data(), footprints.data(), view(words), count, fp, tb, best_b);
            ASSERT_EQ(da, db) << "trial " << trial;
            ++compared;
            if (!da) {
                ++undecided;
                continue;
            }
            ASSERT_EQ(best_a.triangle, best_b.triangle) << "trial " << trial;
            ASSERT_EQ(bits(best_a.t), bits(best_b.t)) << "trial " << trial;
            ASSERT_EQ(bits(best_a.u), bits(best_b.u)) << "trial " << trial;
            ASSERT_EQ(bits(best_a.v), bits(best_b.v)) << "trial " << trial;
            ASSERT_EQ(ta.count, tb.count) << "trial " << trial;
            for (std::uint32_t k = 0; k < ta.count; ++k) ASSERT_EQ(list_a[k], list_b[k]) << "trial " << trial;
            improved += best_a.triangle != before;
            skipped_tested += ta.count < listed + count;
        }
    }
    if (compared == 0) GTEST_SKIP() << "no instruction set with the closest-hit kernel on this CPU";
    EXPECT_GT(improved, 100u);
    EXPECT_GT(undecided, 10u);
    EXPECT_GT(skipped_tested, 100u);
}
