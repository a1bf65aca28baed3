// AnimatedScene: validation, interpolation, snapshots, static part, swept bounds.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/animated_scene.hpp"
#include "beamtrace/error.hpp"
#include "beamtrace/kdtree.hpp"

using namespace beamtrace;

namespace {

bool same_bits(const Float3& a, const Float3& b) { return std::memcmp(&a, &b, sizeof(Float3)) == 0; }

// n random triangles (3 vertices each), every other one moving along a random path of k keyframes
// at uneven times.
AnimatedScene random_animation(std::size_t n, std::size_t k, std::uint32_t seed, std::vector<float>* times_out) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-1.0f, 1.0f), step(0.05f, 0.5f);
    std::vector<float> times(k);
    float t = -0.3f;
    for (auto& x : times) x = (t += step(rng));
    std::vector<Float3> first(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const Float3 c{pos(rng), pos(rng), pos(rng)};
        for (int j = 0; j < 3; ++j) first[3 * i + std::size_t(j)] = c + Float3{pos(rng), pos(rng), pos(rng)} * 0.1f;
    }
    std::vector<Float3> keys;
    for (std::size_t f = 0; f < k; ++f)
        for (std::size_t v = 0; v < 3 * n; ++v)
            keys.push_back((v / 3) % 2 ? first[v] + Float3{pos(rng), pos(rng), pos(rng)} * 0.3f : first[v]);
    std::vector<std::uint32_t> idx(3 * n);
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = std::uint32_t(i);
    if (times_out) *times_out = times;
    return AnimatedScene(times, keys, 3 * n, idx);
}

template <class F>
void expect_error(F&& f, const std::string& words) {
    try {
        f();
        ADD_FAILURE() << "no error; expected one naming: " << words;
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(AnimatedScene, BadInputIsNamed) {
    const std::vector<Float3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    std::vector<Float3> two = v;
    two.insert(two.end(), v.begin(), v.end());
    const std::vector<std::uint32_t> idx = {0, 1, 2};
    const std::vector<float> one_time = {0.0f}, times = {0.0f, 1.0f}, flat = {1.0f, 1.0f};
    expect_error([&] { AnimatedScene(one_time, v, 3, idx); }, "at least two");
    expect_error([&] { AnimatedScene(flat, two, 3, idx); }, "increase strictly");
    expect_error([&] { AnimatedScene(std::vector<float>{0.0f, NAN}, two, 3, idx); }, "not finite");
    expect_error([&] { AnimatedScene(times, v, 3, idx); }, "expected 2 keyframes x 3 vertices");
    expect_error([&] { AnimatedScene(times, two, 3, std::vector<std::uint32_t>{0, 1, 3}); }, "out of range");
    expect_error([&] { AnimatedScene(times, two, 3, std::vector<std::uint32_t>{0, 1}); }, "multiple of 3");
    expect_error([&] { AnimatedScene(times, two, 3, std::vector<std::uint32_t>{}); }, "no triangles");
    std::vector<Float3> bad = two;
    bad[4].y = INFINITY;
    expect_error([&] { AnimatedScene(times, bad, 3, idx); }, "keyframe 1 vertex 1 has a infinite");
    const AnimatedScene ok(times, two, 3, idx);
    expect_error([&] { (void)ok.at(NAN); }, "finite time");
    expect_error([&] { (void)ok.keyframe(2); }, "keyframe 2 of 2");
}

TEST(AnimatedScene, KeyframesExactStillVerticesExactClampedOutside) {
    std::vector<float> times;
    const AnimatedScene a = random_animation(50, 5, 7, &times);
    EXPECT_EQ(a.moving_count(), 25u);
    for (std::size_t k = 0; k < times.size(); ++k)
        for (std::uint32_t v = 0; v < a.vertex_count(); ++v)
            EXPECT_TRUE(same_bits(a.position(v, times[k]), a.keyframe(k)[v])) << k << " " << v;
    for (std::uint32_t v = 0; v < a.vertex_count(); ++v) {
        EXPECT_TRUE(same_bits(a.position(v, times.front() - 5.0f), a.keyframe(0)[v]));
        EXPECT_TRUE(same_bits(a.position(v, times.back() + 5.0f), a.keyframe(times.size() - 1)[v]));
    }
    for (std::uint32_t t = 0; t < a.triangle_count(); ++t) {
        EXPECT_EQ(a.is_moving(t), t % 2 == 1);
        if (a.is_moving(t)) continue;
        for (float time : {0.1f, 0.37f, 0.9f, 1.3f}) {
            const Triangle x = a.triangle_at(t, time), y = a.triangle_at(t, times[0]);
            EXPECT_TRUE(same_bits(x.v0, y.v0) && same_bits(x.v1, y.v1) && same_bits(x.v2, y.v2));
        }
    }
}

TEST(AnimatedScene, SnapshotIsTheInterpolation) {
    std::vector<float> times;
    const AnimatedScene a = random_animation(40, 4, 11, &times);
    for (float t : {times[0], 0.5f * (times[0] + times[1]), times[2], times[3] - 1e-3f}) {
        const Scene s = a.at(t);
        ASSERT_EQ(s.triangle_count(), a.triangle_count());
        for (std::uint32_t i = 0; i < s.triangle_count(); ++i) {
            const Triangle x = a.triangle_at(i, t), &y = s.triangle(i);
            EXPECT_TRUE(same_bits(x.v0, y.v0) && same_bits(x.v1, y.v1) && same_bits(x.v2, y.v2)) << i << " at " << t;
        }
    }
}

TEST(AnimatedScene, StaticPartHoldsWhatDoesNotMove) {
    const AnimatedScene a = random_animation(30, 3, 5, nullptr);
    const Scene& s = a.static_part();
    ASSERT_EQ(s.triangle_count(), a.triangle_count());
    for (std::uint32_t t = 0; t < s.triangle_count(); ++t) {
        EXPECT_EQ(s.is_degenerate(t), a.is_moving(t)) << t;
        if (!a.is_moving(t)) {
            const Triangle x = a.triangle_at(t, 0.0f);
            EXPECT_TRUE(same_bits(x.v0, s.triangle(t).v0) && same_bits(x.v2, s.triangle(t).v2));
        }
    }
}

TEST(AnimatedScene, SweptBoundsHoldTheTriangleAtEveryTime) {
    std::vector<float> times;
    const AnimatedScene a = random_animation(60, 6, 13, &times);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(times.front() - 0.1f, times.back() + 0.1f);
    for (int trial = 0; trial < 200; ++trial) {
        float t0 = u(rng), t1 = u(rng);
        if (t0 > t1) std::swap(t0, t1);
        if (trial % 10 == 0) t1 = std::nextafter(times[2], 10.0f), t0 = std::nextafter(times[2], -10.0f);
        for (std::uint32_t tri = 0; tri < a.triangle_count(); ++tri) {
            const Box b = a.swept_bounds(tri, t0, t1);
            for (int s = 0; s <= 64; ++s) {
                const float t = s == 64 ? t1 : t0 + (t1 - t0) * float(s) / 64.0f;
                if (t > t1) continue;
                const Triangle x = a.triangle_at(tri, t);
                for (const Float3& p : {x.v0, x.v1, x.v2})
                    for (int k = 0; k < 3; ++k)
                        ASSERT_TRUE(p[k] >= b.lower[k] && p[k] <= b.upper[k])
                            << "triangle " << tri << " at " << t << " outside its box over [" << t0 << ", " << t1 << "]";
            }
        }
    }
    for (int k = 0; k < 3; ++k) {
        EXPECT_LE(a.bounds().lower[k], a.swept_bounds(0, times.front(), times.back()).lower[k]);
        EXPECT_GE(a.bounds().upper[k], a.swept_bounds(0, times.front(), times.back()).upper[k]);
    }
}

TEST(AnimatedScene, KdTreeOnSnapshotsEqualsBruteForceOnThem) {
    std::vector<float> times;
    const AnimatedScene a = random_animation(200, 4, 17, &times);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (float t : {times[0], 0.3f * times[1] + 0.7f * times[2], times[3]}) {
        const Scene s = a.at(t);
        const KdTree tree = KdTree::build(s);
        int hits = 0;
        for (int r = 0; r < 500; ++r) {
            const Ray ray{{u(rng) * 2, u(rng) * 2, -3.0f}, 0.0f, {u(rng) * 0.3f, u(rng) * 0.3f, 1.0f}, kInfinity};
            const Hit h = tree.intersect(ray);
            const Hit b = intersect_brute_force(s, ray);
            EXPECT_EQ(h.triangle, b.triangle);
            EXPECT_EQ(h.t, b.t);
            hits += h.hit();
        }
        EXPECT_GT(hits, 50);
    }
}
