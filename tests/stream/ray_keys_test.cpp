// Ray keys: the octahedral direction code has no seam, Morton cells order space, shared points are
// found (a camera's origin, a light the rays end at) and only they.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <map>
#include <span>
#include <tuple>
#include <cmath>
#include <random>
#include <vector>

#include "stream/ray_keys.hpp"

using namespace beamtrace;
using namespace beamtrace::stream;

namespace {

Box unit_box() {
    Box b;
    b.extend(Float3{0, 0, 0});
    b.extend(Float3{1, 1, 1});
    return b;
}

// Cell coordinates (u, v) of an octahedral code (de-interleaved).
std::pair<int, int> cells_of(std::uint32_t code) {
    int u = 0, v = 0;
    for (int b = 0; b < 16; ++b) {
        u |= int((code >> (2 * b)) & 1u) << b;
        v |= int((code >> (2 * b + 1)) & 1u) << b;
    }
    return {u, v};
}

}  // namespace

TEST(StreamKeys, OctahedralCodeIsContinuousButAtTheSquaresEdges) {
    // Directions a hair apart land in cells at most one apart everywhere on the sphere, across the
    // fold (z = 0) and the x, y sign changes of the upper half too; only the unfolded square's edges
    // (x = 0 or y = 0 with z < 0, mirrored there) part neighbours.
    std::mt19937 random(3);
    std::normal_distribution<float> gauss;
    int far_apart = 0;
    for (int i = 0; i < 20000; ++i) {
        Float3 d{gauss(random), gauss(random), gauss(random)};
        if (i % 4 == 0) d.z = 1e-7f * gauss(random);  // near the fold
        const Float3 e{d.x + 1e-5f * gauss(random), d.y + 1e-5f * gauss(random), d.z + 1e-5f * gauss(random)};
        const float l = std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
        if ((d.z < 0.0f || e.z < 0.0f) && (std::fabs(d.x) < 1e-3f * l || std::fabs(d.y) < 1e-3f * l)) continue;
        const auto [u0, v0] = cells_of(octahedral_code(d, 8));
        const auto [u1, v1] = cells_of(octahedral_code(e, 8));
        // Across the fold the unfolded square mirrors at its edge: cells stay neighbours there too.
        if (std::abs(u0 - u1) > 1 || std::abs(v0 - v1) > 1) ++far_apart;
    }
    EXPECT_EQ(far_apart, 0);
}

TEST(StreamKeys, OctahedralCodeSeparatesOppositeDirections) {
    EXPECT_NE(octahedral_code({0, 0, 1}, 8), octahedral_code({0, 0, -1}, 8));
    EXPECT_NE(octahedral_code({1, 0, 0}, 8), octahedral_code({-1, 0, 0}, 8));
    EXPECT_NE(octahedral_code({0, 1, 0}, 8), octahedral_code({0, -1, 0}, 8));
}

TEST(StreamKeys, MortonCellsOfEqualPointsAreEqualAndOfFarPointsDiffer) {
    const Box b = unit_box();
    EXPECT_EQ(morton_cell({0.3f, 0.4f, 0.5f}, b), morton_cell({0.3f, 0.4f, 0.5f}, b));
    EXPECT_NE(morton_cell({0.1f, 0.4f, 0.5f}, b), morton_cell({0.9f, 0.4f, 0.5f}, b));
    EXPECT_EQ(morton_cell({-5.0f, -5.0f, -5.0f}, b), 0u);  // outside: clamped
    EXPECT_EQ(morton_cell({5.0f, 5.0f, 5.0f}, b), (1u << 30) - 1u);
    EXPECT_EQ(morton_cell({1e30f, 1e30f, 1e30f}, b), (1u << 30) - 1u);
    EXPECT_EQ(morton_cell({NAN, 0.5f, 0.5f}, b) & 1u, 0u);  // NaN: the lowest cell on that axis
}

TEST(StreamKeys, FindsTheCameraAndTheLightsAndNothingElse) {
    const Box b = unit_box();
    std::mt19937 random(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const Float3 camera{0.5f, 0.5f, -1.0f}, light_a{0.2f, 0.9f, 0.5f}, light_b{0.8f, 0.9f, 0.5f};
    std::vector<Ray> rays;
    for (int i = 0; i < 3000; ++i) {
        const Float3 p{u(random), u(random), u(random)};
        switch (i % 4) {
            case 0:  // primary: from the camera
                rays.push_back(Ray{camera, 0.0f, p - camera, kInfinity});
                break;
            case 1:  // shadow rays ending just before light a
                rays.push_back(Ray{p, 0.0f, light_a - p, 1.0f - 1e-4f});
                break;
            case 2:  // and b
                rays.push_back(Ray{p, 0.0f, light_b - p, 1.0f - 1e-4f});
                break;
            default:  // scattered rays
                rays.push_back(Ray{p, 0.0f, Float3{u(random) - 0.5f, u(random) - 0.5f, u(random) - 0.5f}, 0.1f});
        }
    }
    const SharedPoints shared = find_shared_points(rays, b, 4096, 0.01f, 16);
    ASSERT_EQ(shared.points.size(), 3u);
    int origins = 0, ends = 0;
    for (const SharedPoint& p : shared.points) (p.ends ? ends : origins)++;
    EXPECT_EQ(origins, 1);
    EXPECT_EQ(ends, 2);
    std::vector<std::uint32_t> keys(rays.size());
    make_keys(rays, b, shared, keys);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const bool pencil = (keys[i] & kPencilBit) != 0;
        EXPECT_EQ(pencil, i % 4 != 3) << "ray " << i;
    }
}

TEST(StreamKeys, TheSampleCountsOriginsSeenTwiceButNotSharedPoints) {
    // Ambient-occlusion-like rays: 16 from each of 4,000 points, shuffled; diffuse-like: one a point;
    // camera rays: one origin (a shared point, not a repeat).
    const Box b = unit_box();
    std::mt19937 random(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Float3> points(4000);
    for (Float3& p : points) p = Float3{u(random), u(random), u(random)};
    std::vector<Ray> ao, diffuse, camera;
    for (const Float3& p : points) {
        for (int k = 0; k < 16; ++k) ao.push_back(Ray{p, 0.0f, Float3{u(random) - 0.5f, u(random), 0.25f}, 0.2f});
        diffuse.push_back(Ray{p, 0.0f, Float3{u(random) - 0.5f, u(random), 0.25f}, kInfinity});
        camera.push_back(Ray{Float3{0.5f, 0.5f, -1.0f}, 0.0f, p - Float3{0.5f, 0.5f, -1.0f}, kInfinity});
    }
    std::shuffle(ao.begin(), ao.end(), random);
    EXPECT_GT(find_shared_points(ao, b, 4096, 0.01f, 16).repeated_origins, 100u);
    EXPECT_EQ(find_shared_points(diffuse, b, 4096, 0.01f, 16).repeated_origins, 0u);
    const SharedPoints at_camera = find_shared_points(camera, b, 4096, 0.01f, 16);
    EXPECT_EQ(at_camera.points.size(), 1u);
    EXPECT_EQ(at_camera.repeated_origins, 0u);
}

// The sample counted with ordered maps, filled in sample order: what find_shared_points computes
// with sorted vectors, written the plain way.
SharedPoints shared_points_by_maps(std::span<const Ray> rays, const Box& box, int sample_rays, float fraction,
                                   int max_points) {
    SharedPoints shared;
    shared.radius = 1e-3f * std::sqrt(dot(box.extent(), box.extent()));
    const std::size_t n = rays.size(), samples = std::min<std::size_t>(n, std::size_t(sample_rays));
    std::map<std::tuple<float, float, float>, int> origins;
    std::map<std::tuple<std::int64_t, std::int64_t, std::int64_t>, std::pair<Float3, int>> ends;
    const float cell = 2.0f * shared.radius;
    for (std::size_t s = 0; s < samples; ++s) {
        const Ray& r = rays[s * n / samples];
        ++origins[{r.org.x, r.org.y, r.org.z}];
        const Float3 e = r.org + r.dir * r.tfar;
        auto& c = ends[{std::int64_t(std::floor(e.x / cell)), std::int64_t(std::floor(e.y / cell)),
                        std::int64_t(std::floor(e.z / cell))}];
        c.first = c.first + e;
        ++c.second;
    }
    const int needed = std::max(2, int(std::ceil(double(fraction) * double(samples))));
    std::vector<std::pair<int, SharedPoint>> found;
    for (const auto& [o, count] : origins) {
        if (count >= needed)
            found.push_back({count, SharedPoint{{std::get<0>(o), std::get<1>(o), std::get<2>(o)}, false}});
        else
            shared.repeated_origins += std::size_t(count - 1);
    }
    for (const auto& [key, c] : ends)
        if (c.second >= needed) found.push_back({c.second, SharedPoint{c.first * (1.0f / float(c.second)), true}});
    std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& f : found)
        if (int(shared.points.size()) < max_points) shared.points.push_back(f.second);
    return shared;
}

TEST(StreamKeys, TheSampleFindsWhatOrderedMapsFind) {
    // Origins from a few points (one of them as +0 and as -0 in x), rays ending near a few lights,
    // shuffled: the same points, bit for bit, in the same order, and the same repeat count.
    const Box b = unit_box();
    std::mt19937 random(9);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const Float3 lights[3] = {{0.2f, 0.9f, 0.3f}, {0.8f, 0.95f, 0.6f}, {0.5f, 0.9f, 0.5f}};
    for (int trial = 0; trial < 4; ++trial) {
        std::vector<Float3> pool(1000);  // origins a few rays each share (repeats, not shared points)
        for (Float3& p : pool) p = Float3{u(random), u(random), u(random)};
        std::vector<Ray> rays;
        for (int i = 0; i < 20000; ++i) {
            const int kind = int(random() % 6);
            Float3 o{u(random), u(random), u(random)};
            if (kind == 0) o = Float3{random() % 2 ? 0.0f : -0.0f, 0.25f, 0.5f};
            if (kind == 1) o = Float3{0.75f, 0.125f, float(random() % 4) * 0.25f};
            if (kind == 5) o = pool[random() % pool.size()];
            if (kind >= 2 && kind <= 4) {
                const Float3 l = lights[kind - 2] + Float3{u(random), u(random), u(random)} * 1e-5f;
                rays.push_back(Ray{o, 0.0f, l - o, 1.0f});
            } else {
                rays.push_back(Ray{o, 0.0f, Float3{u(random) - 0.5f, u(random) - 0.5f, u(random)}, 0.3f});
            }
        }
        std::shuffle(rays.begin(), rays.end(), random);
        for (int samples : {64, 1000, 4096}) {
            const SharedPoints got = find_shared_points(rays, b, samples, 0.01f, 16);
            const SharedPoints want = shared_points_by_maps(rays, b, samples, 0.01f, 16);
            if (samples == 4096) {  // the case is not empty: origins, ends and repeats were found
                EXPECT_GE(want.points.size(), 6u);
                EXPECT_GT(want.repeated_origins, 10u);
            }
            ASSERT_EQ(got.repeated_origins, want.repeated_origins) << "trial " << trial << ", " << samples;
            ASSERT_EQ(got.points.size(), want.points.size()) << "trial " << trial << ", " << samples;
            for (std::size_t k = 0; k < got.points.size(); ++k) {
                EXPECT_EQ(got.points[k].ends, want.points[k].ends);
                for (int a = 0; a < 3; ++a)
                    EXPECT_EQ(std::bit_cast<std::uint32_t>(got.points[k].at[a]),
                              std::bit_cast<std::uint32_t>(want.points[k].at[a]))
                        << "point " << k << " axis " << a;
            }
        }
    }
}

TEST(StreamKeys, RaysThatDescribeNoSegmentGetTheirOwnKey) {
    const Box b = unit_box();
    const std::vector<Ray> rays = {Ray{{0, 0, 0}, 0.0f, {0, 0, 0}, 1.0f}, Ray{{NAN, 0, 0}, 0.0f, {1, 0, 0}, 1.0f},
                                   Ray{{0, 0, 0}, 2.0f, {1, 0, 0}, 1.0f}, Ray{{0, 0, 0}, 0.0f, {1, 0, 0}, 1.0f}};
    std::vector<std::uint32_t> keys(rays.size());
    make_keys(rays, b, SharedPoints{}, keys);
    EXPECT_EQ(keys[0], kNoSegmentKey);
    EXPECT_EQ(keys[1], kNoSegmentKey);
    EXPECT_EQ(keys[2], kNoSegmentKey);
    EXPECT_NE(keys[3], kNoSegmentKey);
}

TEST(StreamKeys, EveryInstructionSetGivesTheReferenceKeysBitForBit) {
    // Rays of every kind the keys tell apart: through shared origins and end points (within the
    // radius and just outside it), anywhere, outside the box, with infinite tfar, negative and
    // signed-zero direction components, and ones that describe no segment; counts that leave a tail
    // after the last whole batch.
    const Box b = unit_box();
    SharedPoints shared;
    shared.radius = 1e-3f;
    shared.points = {SharedPoint{{0.5f, 0.25f, 0.75f}, false}, SharedPoint{{0.1f, 0.9f, 0.3f}, true},
                     SharedPoint{{0.7f, 0.7f, 0.2f}, true}, SharedPoint{{0.5f, 0.25f, 0.75f}, true}};
    std::mt19937 random(11);
    std::uniform_real_distribution<float> unit(-0.2f, 1.2f), dir(-1.0f, 1.0f);
    std::uniform_int_distribution<int> kind(0, 11);
    std::vector<Ray> rays;
    for (int i = 0; i < 4099; ++i) {
        Ray r{{unit(random), unit(random), unit(random)}, 0.0f, {dir(random), dir(random), dir(random)}, 1.0f};
        switch (kind(random)) {
            case 0:
                r.org = shared.points[0].at;
                break;
            case 1:
            case 2: {  // ends at (or within a hair of) an end point
                const Float3 at = shared.points[1 + i % 2].at;
                const float miss = i % 3 == 0 ? 2e-3f : 0.0f;
                r.dir = Float3{at.x + miss, at.y, at.z} - r.org;
                r.tfar = 1.0f;
                break;
            }
            case 3:
                r.tfar = kInfinity;
                break;
            case 4:
                r.dir.z = -std::fabs(r.dir.z);
                break;
            case 5:
                r.dir = Float3{-0.0f, 0.0f, -1.0f};
                break;
            case 6:
                r.org.x = NAN;
                break;
            case 7:
                r.dir = Float3{0, 0, 0};
                break;
            case 8:
                r.tnear = 2.0f;
                break;
            case 9:
                r.dir.y = kInfinity;
                break;
            case 10:
                r.org = Float3{-5.0f, 40.0f, 0.5f};
                break;
            default:
                break;
        }
        rays.push_back(r);
    }
    for (const SharedPoints& points : {shared, SharedPoints{}}) {
        for (std::size_t n : {std::size_t(0), std::size_t(3), std::size_t(17), rays.size()}) {
            const std::span<const Ray> some(rays.data(), n);
            std::vector<std::uint32_t> reference(n), keys(n);
            make_keys(some, b, points, reference, Isa::scalar);
            for (Isa isa : {Isa::sse42, Isa::avx2, Isa::avx512}) {
                if (!isa_available(isa)) continue;
                std::fill(keys.begin(), keys.end(), 0u);
                make_keys(some, b, points, keys, isa);
                for (std::size_t i = 0; i < n; ++i)
                    ASSERT_EQ(keys[i], reference[i]) << isa_name(isa) << " ray " << i << " of " << n;
            }
        }
    }
    // The mix above reaches every kind of key.
    std::vector<std::uint32_t> keys(rays.size());
    make_keys(rays, b, shared, keys, best_isa());
    int pencils[4] = {}, cells = 0, none = 0;
    for (std::uint32_t k : keys) {
        if (k == kNoSegmentKey)
            ++none;
        else if (k & kPencilBit)
            ++pencils[(k >> kPointShift) & 15u];
        else
            ++cells;
    }
    EXPECT_GT(pencils[0], 0);
    EXPECT_GT(pencils[1], 0);
    EXPECT_GT(pencils[2], 0);
    EXPECT_GT(cells, 0);
    EXPECT_GT(none, 0);
}
