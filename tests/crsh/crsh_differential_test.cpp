// CRSH and RAH against brute force: the same watertight test on the triangles that survive the
// hierarchy and the same tie rule (smallest t, then smallest id), so every closest hit must equal
// brute force's bit for bit (t, triangle, u, v) and every occlusion answer must be the same, for
// every kind of ray, partition and setting.
#include <gtest/gtest.h>

#include <bit>
#include <string>

#include "beamtrace/crsh.hpp"
#include "beamtrace/kdtree.hpp"
#include "crsh_test_rays.hpp"
#include "test_scenes.hpp"

using namespace beamtrace;

namespace {

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

// Brute force's answers to a ray set, computed once.
struct Reference {
    std::vector<Ray> rays;
    std::vector<Hit> hits;
    std::vector<std::uint8_t> occluded;
};

Reference reference(const Scene& scene, std::vector<Ray> rays) {
    Reference r;
    r.rays = std::move(rays);
    for (const Ray& ray : r.rays) {
        r.hits.push_back(intersect_brute_force(scene, ray));
        r.occluded.push_back(occluded_brute_force(scene, ray) ? 1 : 0);
    }
    return r;
}

// Every answer of crsh equals brute force's; returns the number of hits.
int expect_brute_force_answers(const Crsh& crsh, const Reference& ref, int threads, const std::string& what) {
    const std::vector<Ray>& rays = ref.rays;
    std::vector<Hit> hits(rays.size());
    std::vector<std::uint8_t> occluded(rays.size(), 7);
    crsh.intersect(rays, hits, {threads, nullptr});
    crsh.occluded(rays, occluded, {threads, nullptr});
    int count = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit& b = ref.hits[i];
        const Hit& a = hits[i];
        EXPECT_EQ(a.triangle, b.triangle) << what << ", ray " << i;
        if (a.triangle != b.triangle) return count;
        if (b.hit()) {
            ++count;
            EXPECT_EQ(bits(a.t), bits(b.t)) << what << ", ray " << i;
            EXPECT_EQ(bits(a.u), bits(b.u)) << what << ", ray " << i;
            EXPECT_EQ(bits(a.v), bits(b.v)) << what << ", ray " << i;
        }
        EXPECT_EQ(occluded[i], ref.occluded[i]) << what << ", ray " << i;
        if (occluded[i] != ref.occluded[i]) return count;
    }
    return count;
}

std::vector<std::uint32_t> partition(std::size_t triangles, std::uint32_t per_object) {
    std::vector<std::uint32_t> objects(triangles);
    // Ids neither dense nor in triangle order: objects are whatever shares an id.
    for (std::size_t t = 0; t < triangles; ++t) objects[t] = 1000u - std::uint32_t(t / per_object) * 3u;
    return objects;
}

struct Variant {
    std::string name;
    CrshSettings settings;
};

std::vector<Variant> variants() {
    std::vector<Variant> v;
    v.push_back({"crsh", CrshSettings{}});
    CrshSettings rah;
    rah.sort = false;
    rah.object_spheres = false;
    v.push_back({"rah", rah});
    for (int fanout : {2, 5, 16, 64}) {
        CrshSettings s;
        s.fanout = fanout;
        v.push_back({"fanout " + std::to_string(fanout), s});
    }
    for (int levels : {1, 3, 4}) {
        CrshSettings s;
        s.levels = levels;
        v.push_back({"levels " + std::to_string(levels), s});
    }
    CrshSettings end;
    end.key = CrshKey::end_point;
    v.push_back({"end-point keys", end});
    CrshSettings coarse;
    coarse.key_position_bits = 0;
    v.push_back({"direction-only keys", coarse});
    CrshSettings bounded;
    bounded.segment_bound = true;
    bounded.key_position_bits = 3;
    v.push_back({"segment bound", bounded});
    rah.segment_bound = true;
    v.push_back({"rah, segment bound", rah});
    return v;
}

void check_scene(const Scene& scene, unsigned seed) {
    const Box& box = scene.bounds();
    const std::vector<std::pair<std::string, Reference>> sets = {
        {"random", reference(scene, test::random_rays(box, 1500, seed))},
        {"axis", reference(scene, test::axis_rays(scene, 800, seed + 1))},
        {"camera", reference(scene, test::camera_rays(box, 1500, seed + 2))},
        {"shadow", reference(scene, test::shadow_rays(box, 1500, seed + 3))},
        {"ao", reference(scene, test::ao_rays(box, 1200, seed + 4))}};
    const std::vector<std::uint32_t> objects = partition(scene.triangle_count(), 7);
    int hits = 0;
    for (const Variant& v : variants()) {
        CrshSettings s = v.settings;
        if (s.object_spheres) s.object_of_triangle = objects;
        const Crsh crsh(scene, s);
        for (const auto& [name, rays] : sets) hits += expect_brute_force_answers(crsh, rays, 1, v.name + ", " + name);
    }
    EXPECT_GT(hits, 0);
}

}  // namespace

TEST(CrshDifferential, RandomSoupEqualsBruteForce) { check_scene(test::random_soup(600, 1), 10); }

TEST(CrshDifferential, BoxesSharingFacesEqualBruteForce) { check_scene(test::stacked_boxes(40, 2), 20); }

TEST(CrshDifferential, SinglePlaneEqualsBruteForce) { check_scene(test::single_plane(16), 30); }

TEST(CrshDifferential, PartitionsAndThreadsChangeNoAnswer) {
    const Scene scene = test::random_soup(800, 3);
    const Reference rays = reference(scene, test::shadow_rays(scene.bounds(), 3000, 4));
    const std::vector<std::uint32_t> each = partition(scene.triangle_count(), 1);
    const std::vector<std::uint32_t> big = partition(scene.triangle_count(), 300);
    for (const auto* objects : {&each, &big}) {
        CrshSettings s;
        s.object_of_triangle = *objects;
        const Crsh crsh(scene, s);
        expect_brute_force_answers(crsh, rays, 1, "one thread");
        expect_brute_force_answers(crsh, rays, 2, "two threads");
        expect_brute_force_answers(crsh.with_key(CrshKey::end_point), rays, 3, "end point, three threads");
    }
}

TEST(CrshDifferential, FarFromTheOriginEqualsBruteForce) {
    // The same soup moved a million units away: the bounds' arithmetic must not cull by rounding.
    const Scene soup = test::random_soup(400, 5);
    std::vector<Float3> moved(soup.vertices().begin(), soup.vertices().end());
    for (Float3& p : moved) p = p * 10.0f + Float3{1e6f, -2e6f, 5e5f};
    const Scene scene(moved, soup.indices());
    const Crsh crsh(scene);
    const Box& box = scene.bounds();
    EXPECT_GT(expect_brute_force_answers(crsh, reference(scene, test::camera_rays(box, 2000, 6)), 1, "camera"), 0);
    expect_brute_force_answers(crsh.with_key(CrshKey::end_point), reference(scene, test::shadow_rays(box, 2000, 7)), 1,
                               "shadow");
    expect_brute_force_answers(crsh, reference(scene, test::ao_rays(box, 2000, 8)), 1, "ao");
}

TEST(CrshDifferential, PacketsEqualSpansOfRays) {
    const Scene scene = test::stacked_boxes(30, 9);
    const std::vector<Ray> rays = test::camera_rays(scene.bounds(), 16 * 40, 10);
    std::vector<Packet16> packets(40);
    for (std::size_t p = 0; p < packets.size(); ++p) {
        packets[p].active = 0xFFFFu & ~(0x1111u << (p % 4));  // a few lanes off
        for (int i = 0; i < 16; ++i) packets[p].set_ray(i, rays[p * 16 + std::size_t(i)]);
    }
    const Crsh crsh(scene);
    std::vector<PacketHits16> hits(packets.size());
    std::vector<std::uint32_t> occluded(packets.size());
    crsh.intersect(packets, hits);
    crsh.occluded(packets, occluded, {2, nullptr});
    for (std::size_t p = 0; p < packets.size(); ++p)
        for (int i = 0; i < 16; ++i) {
            const bool on = (packets[p].active >> i) & 1u;
            const Ray& r = rays[p * 16 + std::size_t(i)];
            const Hit want = on ? intersect_brute_force(scene, r) : Hit{};
            EXPECT_EQ(hits[p].triangle[i], want.triangle);
            EXPECT_EQ(bits(hits[p].t[i]), bits(want.t));
            EXPECT_EQ((occluded[p] >> i) & 1u, on && occluded_brute_force(scene, r) ? 1u : 0u);
            EXPECT_EQ(crsh.intersect(r).triangle, intersect_brute_force(scene, r).triangle);
            EXPECT_EQ(crsh.occluded(r), occluded_brute_force(scene, r));
        }
}
