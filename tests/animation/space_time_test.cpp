// SpaceTimeClassification: a ray at time t answers as kd1 (and brute force) on scene.at(t), for
// closest hits and occlusion, spans on one and two threads, single rays; bins of past calls freed;
// bad input named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/error.hpp"
#include "beamtrace/kdtree.hpp"
#include "beamtrace/space_time_classification.hpp"

using namespace beamtrace;

namespace {

// n small random triangles; every third one still, the others on a random path of k keyframes.
AnimatedScene soup_in_motion(std::size_t n, std::size_t k, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-1.0f, 1.0f);
    std::vector<float> times(k);
    for (std::size_t i = 0; i < k; ++i) times[i] = float(i) * 0.25f;
    std::vector<Float3> first(3 * n), keys;
    for (std::size_t i = 0; i < n; ++i) {
        const Float3 c{pos(rng), pos(rng), pos(rng)};
        for (int j = 0; j < 3; ++j) first[3 * i + std::size_t(j)] = c + Float3{pos(rng), pos(rng), pos(rng)} * 0.15f;
    }
    std::vector<Float3> drift(n);
    for (auto& d : drift) d = Float3{pos(rng), pos(rng), pos(rng)} * 0.2f;
    for (std::size_t f = 0; f < k; ++f)
        for (std::size_t v = 0; v < 3 * n; ++v) {
            const std::size_t t = v / 3;
            keys.push_back(t % 3 == 0 ? first[v] : first[v] + drift[t] * float(f) + Float3{pos(rng), pos(rng), pos(rng)} * 0.02f);
        }
    std::vector<std::uint32_t> idx(3 * n);
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = std::uint32_t(i);
    return AnimatedScene(times, keys, 3 * n, idx);
}

std::vector<Ray> random_rays(int n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f);
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        const Float3 o{u(rng), u(rng), u(rng)}, target{u(rng) * 0.5f, u(rng) * 0.5f, u(rng) * 0.5f};
        rays.push_back(Ray{o, 0.0f, target - o, i % 4 == 0 ? 0.7f : kInfinity});
    }
    return rays;
}

void expect_as_snapshots(const SpaceTimeClassification& st, const std::vector<Ray>& rays,
                         const std::vector<float>& times, int threads) {
    std::vector<Hit> hits(rays.size());
    std::vector<std::uint8_t> occ(rays.size());
    st.intersect(rays, times, hits, QueryOptions{threads, nullptr});
    st.occluded(rays, times, occ, QueryOptions{threads, nullptr});
    std::size_t hit_count = 0, moving_hits = 0;
    std::vector<float> distinct = times;
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    for (float t : distinct) {
        const Scene snapshot = st.scene().at(t);
        const KdTree kd = KdTree::build(snapshot);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (times[i] != t) continue;
            const Hit want = intersect_brute_force(snapshot, rays[i]);
            const Hit k = kd.intersect(rays[i]);
            ASSERT_EQ(hits[i].triangle, want.triangle) << "ray " << i << " at " << t;
            ASSERT_EQ(hits[i].t, want.t) << "ray " << i << " at " << t;
            ASSERT_EQ(hits[i].u, want.u) << "ray " << i << " at " << t;
            ASSERT_EQ(hits[i].v, want.v) << "ray " << i << " at " << t;
            ASSERT_EQ(hits[i].t, k.t) << "kd1, ray " << i << " at " << t;  // kd1: same t (ties: its own id)
            ASSERT_EQ(occ[i] != 0, kd.occluded(rays[i])) << "occlusion, ray " << i << " at " << t;
            hit_count += want.hit();
            moving_hits += want.hit() && st.scene().is_moving(want.triangle);
            if (i % 11 == 0) {
                const Hit one = st.intersect(rays[i], t);
                ASSERT_EQ(one.triangle, want.triangle);
                ASSERT_EQ(one.t, want.t);
                ASSERT_EQ(st.occluded(rays[i], t), occ[i] != 0);
            }
        }
    }
    EXPECT_GT(hit_count, rays.size() / 10);
    EXPECT_GT(moving_hits, rays.size() / 20) << "the moving part answers nothing: the test tests too little";
}

}  // namespace

TEST(SpaceTime, AnswersAsKd1AndBruteForceOnTheSnapshot) {
    const AnimatedScene scene = soup_in_motion(600, 5, 3);
    const std::vector<float> shared_times = {-0.5f, 0.0f, 0.1f, 0.25f, 0.4f, 0.61f, 0.8f, 1.0f, 1.7f};
    for (int bins : {0, 1, 7}) {
        SpaceTimeSettings s;
        s.time_bins = bins;
        const SpaceTimeClassification st(scene, s);
        const std::vector<Ray> rays = random_rays(4000, 5 + std::uint32_t(bins));
        std::vector<float> times(rays.size());
        for (std::size_t i = 0; i < times.size(); ++i) times[i] = shared_times[(i * 7) % shared_times.size()];
        expect_as_snapshots(st, rays, times, 1);
        expect_as_snapshots(st, rays, times, 2);
        EXPECT_GT(st.stats().moving_cells, 0u);
        EXPECT_EQ(st.stats().moving_triangles, scene.moving_count());
    }
}

// Calls whose rays share a start point (camera rays) or an end point (shadow rays to a point light)
// go to light buffers around that point, in the moving part as in the static one: the same answers.
TEST(SpaceTime, LightBuffersAnswerAsKd1AndBruteForceOnTheSnapshot) {
    const AnimatedScene scene = soup_in_motion(600, 5, 4);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f);
    const Float3 eye{0.1f, 2.2f, -2.5f}, light{-0.3f, 2.0f, 0.4f};
    std::vector<Ray> from_eye, to_light;
    for (int i = 0; i < 3000; ++i) {
        const Float3 target{u(rng) * 0.5f, u(rng) * 0.5f, u(rng) * 0.5f};
        from_eye.push_back(Ray{eye, 0.0f, target - eye, kInfinity});
        const Float3 o{u(rng), u(rng), u(rng)};
        to_light.push_back(Ray{o, 0.0f, light - o, 1.0f - 1e-4f});
    }
    for (const std::vector<float>& offsets : {std::vector<float>{0.3f}, std::vector<float>{0.1f, 0.55f, 0.9f}}) {
        const SpaceTimeClassification st(scene);
        std::vector<float> times(from_eye.size());
        for (std::size_t i = 0; i < times.size(); ++i) times[i] = offsets[i % offsets.size()];
        expect_as_snapshots(st, from_eye, times, 1);
        expect_as_snapshots(st, to_light, times, 2);
    }
}

// Packets (4x4, times per lane), the static part by the classification or by the kd-tree's packet
// traversal (static_packets): every closest hit at brute force's t on the snapshot, naming brute
// force's triangle or another one the ray meets at that t (a tie); occlusion as kd1 on the snapshot.
TEST(SpaceTime, PacketsAnswerAsTheSnapshot) {
    const AnimatedScene scene = soup_in_motion(600, 5, 6);
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f);
    const Float3 eye{0.1f, 2.2f, -2.5f}, light{-0.3f, 2.0f, 0.4f};
    std::vector<Packet16> camera(200), shadow(200);
    std::vector<float> slot_times(200 * 16);
    const float offsets[3] = {0.15f, 0.5f, 0.95f};
    for (std::size_t p = 0; p < camera.size(); ++p)
        for (int i = 0; i < 16; ++i) {
            const Float3 target{u(rng) * 0.4f + 0.01f * float(i % 4), u(rng) * 0.4f + 0.01f * float(i / 4), u(rng) * 0.4f};
            camera[p].set_ray(i, Ray{eye, 0.0f, target - eye, kInfinity});
            const Float3 o{u(rng), u(rng), u(rng)};
            shadow[p].set_ray(i, Ray{o, 0.0f, light - o, 1.0f - 1e-4f});
            if ((p + std::size_t(i)) % 5 != 0) {  // some lanes off
                camera[p].active |= 1u << i;
                shadow[p].active |= 1u << i;
            }
            slot_times[p * 16 + std::size_t(i)] = offsets[(p * 16 + std::size_t(i)) % 3];
        }
    for (bool packets : {false, true}) {
        SpaceTimeSettings s;
        s.static_packets = packets;
        const SpaceTimeClassification st(scene, s);
        std::vector<PacketHits16> hits(camera.size());
        std::vector<std::uint32_t> occ(shadow.size());
        st.intersect(camera, slot_times, hits, QueryOptions{2, nullptr});
        st.occluded(shadow, slot_times, occ, QueryOptions{1, nullptr});
        {
            // Two threads over more packets than one part takes (the static packets are reversed and
            // traced block by block on each thread): the same bits as one thread.
            std::vector<Packet16> many;
            std::vector<float> many_times;
            for (int copy = 0; copy < 3; ++copy) {
                many.insert(many.end(), shadow.begin(), shadow.end());
                many_times.insert(many_times.end(), slot_times.begin(), slot_times.end());
            }
            std::vector<std::uint32_t> two(many.size());
            st.occluded(many, many_times, two, QueryOptions{2, nullptr});
            for (std::size_t p = 0; p < many.size(); ++p)
                ASSERT_EQ(two[p], occ[p % shadow.size()]) << "packets " << packets << " packet " << p;
        }
        std::size_t moving_hits = 0;
        for (const float t : offsets) {
            const Scene snapshot = scene.at(t);
            const KdTree kd = KdTree::build(snapshot);
            for (std::size_t p = 0; p < camera.size(); ++p)
                for (int i = 0; i < 16; ++i) {
                    const std::size_t slot = p * 16 + std::size_t(i);
                    if (slot_times[slot] != t) continue;
                    const bool on = (camera[p].active >> i) & 1u;
                    const Hit got = hits[p].hit(i);
                    if (!on) {
                        ASSERT_FALSE(got.hit()) << "inactive lane " << slot;
                        ASSERT_EQ((occ[p] >> i) & 1u, 0u) << "inactive lane " << slot;
                        continue;
                    }
                    const Hit want = intersect_brute_force(snapshot, camera[p].ray(i));
                    ASSERT_EQ(got.t, want.t) << "packets " << packets << " slot " << slot;
                    if (got.triangle != want.triangle) {
                        ASSERT_TRUE(packets) << "the classification names brute force's triangle, slot " << slot;
                        const Scene alone(snapshot.vertices(), snapshot.indices().subspan(3 * std::size_t(got.triangle), 3));
                        ASSERT_EQ(intersect_brute_force(alone, camera[p].ray(i)).t, want.t) << "a tie, slot " << slot;
                    }
                    moving_hits += want.hit() && scene.is_moving(want.triangle);
                    ASSERT_EQ(((occ[p] >> i) & 1u) != 0, kd.occluded(shadow[p].ray(i))) << "occlusion, slot " << slot;
                }
        }
        EXPECT_GT(moving_hits, 100u) << "the moving part answers nothing: the test tests too little";
    }
}

TEST(SpaceTime, StillSceneIsTheStaticClassification) {
    const Scene base = soup_in_motion(300, 2, 8).at(0.0f);
    std::vector<Float3> keys(base.vertices().begin(), base.vertices().end());
    keys.insert(keys.end(), base.vertices().begin(), base.vertices().end());
    const std::vector<std::uint32_t> idx(base.indices().begin(), base.indices().end());
    const AnimatedScene still(std::vector<float>{0.0f, 1.0f}, keys, base.vertex_count(), idx);
    EXPECT_EQ(still.moving_count(), 0u);
    const SpaceTimeClassification st(still);
    const std::vector<Ray> rays = random_rays(1000, 9);
    std::vector<float> times(rays.size(), 0.5f);
    std::vector<Hit> hits(rays.size());
    st.intersect(rays, times, hits);
    for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(hits[i].t, intersect_brute_force(base, rays[i]).t) << i;
    EXPECT_EQ(st.stats().bins_made, 0u);
}

TEST(SpaceTime, BinsOfPastCallsAreFreed) {
    const AnimatedScene scene = soup_in_motion(400, 5, 4);
    SpaceTimeSettings s;
    s.time_bins = 16;
    s.keep_calls = 1;
    const SpaceTimeClassification st(scene, s);
    const std::vector<Ray> rays = random_rays(500, 2);
    std::vector<Hit> hits(rays.size());
    std::size_t first_peak = 0;
    for (int frame = 0; frame < 16; ++frame) {
        const std::vector<float> times(rays.size(), float(frame) / 16.0f + 0.01f);
        st.intersect(rays, times, hits);
        if (frame == 1) first_peak = st.stats().moving_memory_bytes;
    }
    const SpaceTimeStats stats = st.stats();
    EXPECT_EQ(stats.bins_made, 16u);
    EXPECT_GE(stats.bins_freed, 14u);
    EXPECT_LE(stats.bins_resident, 2u);
    EXPECT_LE(double(stats.moving_memory_bytes), 2.5 * double(first_peak)) << "memory grows with frames";
    st.clear();
    EXPECT_EQ(st.stats().bins_resident, 0u);
    EXPECT_EQ(st.stats().moving_memory_bytes, 0u);
}

// The static part's kd-tree is binned above SpaceTimeSettings::static_binned_above references
// unless the caller's rules say otherwise; answers as ever.
TEST(SpaceTime, StaticTreeIsBinnedAboveItsThreshold) {
    const AnimatedScene scene = soup_in_motion(900, 5, 6);  // 300 still triangles
    const std::vector<Ray> rays = random_rays(3000, 7);
    std::vector<float> times(rays.size());
    for (std::size_t i = 0; i < times.size(); ++i) times[i] = float(i % 5) * 0.2f;
    SpaceTimeSettings s;
    s.static_binned_above = 32;
    const SpaceTimeClassification binned(scene, s);
    EXPECT_GT(binned.static_part().kd_tree().stats().binned_splits, 0u);
    expect_as_snapshots(binned, rays, times, 1);
    s.static_binned_above = 0;
    EXPECT_EQ(SpaceTimeClassification(scene, s).static_part().kd_tree().stats().binned_splits, 0u);
    KdBuildRules rules;
    rules.binned_above = 64;
    EXPECT_GT(SpaceTimeClassification(scene, s, rules).static_part().kd_tree().stats().binned_splits, 0u);
    s.static_binned_above = -1;
    try {
        SpaceTimeClassification st(scene, s);
        ADD_FAILURE() << "no error for static_binned_above -1";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("static_binned_above"), std::string::npos) << e.what();
    }
}

TEST(SpaceTime, BadInputIsNamed) {
    const AnimatedScene scene = soup_in_motion(50, 3, 1);
    SpaceTimeSettings bad;
    bad.time_bins = -1;
    EXPECT_THROW(SpaceTimeClassification(scene, bad), Error);
    bad = {};
    bad.keep_calls = 0;
    EXPECT_THROW(SpaceTimeClassification(scene, bad), Error);
    const SpaceTimeClassification st(scene);
    const std::vector<Ray> rays = random_rays(4, 1);
    std::vector<Hit> hits(4);
    try {
        st.intersect(rays, std::vector<float>(3, 0.0f), hits);
        ADD_FAILURE() << "no error for 3 times and 4 rays";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("3 times for 4 rays"), std::string::npos) << e.what();
    }
    try {
        st.intersect(rays, std::vector<float>{0.0f, 0.1f, NAN, 0.2f}, hits);
        ADD_FAILURE() << "no error for a NaN time";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("ray 2 has a time"), std::string::npos) << e.what();
    }
}
