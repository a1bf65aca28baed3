// Robust.DegenerateScene*: scenes that push the builders: sliver and needle triangles, zero-area
// triangles mixed in, coincident duplicates (same and opposite winding), a single flat plane (every
// kd split coplanar), every triangle in one point or on one line, a single triangle, coordinates
// near float's largest value. Every engine builds; no degenerate triangle is ever hit; zero
// `mismatch` against Embree and exact geometry wherever a scene has something to hit.
#include <gtest/gtest.h>

#include <cfloat>
#include <cstdio>
#include <random>

#include "extremes/engine_checks.hpp"
#include "extremes/exact_reference.hpp"
#include "kdtree/test_scenes.hpp"
#include "rays/ray_set.hpp"

namespace beamtrace::test {
namespace {

using workload::Mode;

scenes::SceneSource source_of(const std::string& name, Scene scene) {
    const scenes::Camera camera = scenes::frame_from_outside(scene.bounds());
    return scenes::SceneSource{name, std::move(scene), camera, name};
}

EngineChoice fields() {
    EngineChoice choice;
    choice.options.vlf.directions = 129;
    choice.options.vlf.tiles = 32;
    return choice;
}

// Camera rays (an image: MLRTA's tiles) and random rays, closest hit and occlusion: zero mismatch.
void expect_clean(const scenes::SceneSource& source) {
    const auto engines = build_engines(source.scene, fields());
    for (Mode mode : {Mode::primary, Mode::shadow, Mode::ao}) {
        workload::WorkloadConfig config;
        config.mode = mode;
        config.width = config.height = mode == Mode::ao ? 16 : 32;
        config.ao_rays = 4;
        expect_exact_engines_clean(check_engines(engines, workload::make_workload(source, config),
                                                 source.name + " " + workload::to_string(mode), true));
    }
    for (Mode mode : {Mode::primary, Mode::shadow}) {
        workload::RaySet rays = workload::make_random_rays(source.scene.bounds(), 3000, 11, mode);
        expect_exact_engines_clean(check_engines(engines, workload_for(source, std::move(rays)),
                                                 source.name + " random " + workload::to_string(mode), true));
    }
}

// Every engine builds and no ray finds anything (the scene has nothing to hit).
void expect_nothing_to_hit(const scenes::SceneSource& source) {
    EXPECT_EQ(source.scene.degenerate_count(), source.scene.triangle_count()) << source.name;
    const auto engines = build_engines(source.scene, fields());
    Box around = source.scene.bounds();
    around.extend(around.lower - Float3{1, 1, 1});
    around.extend(around.upper + Float3{1, 1, 1});
    std::vector<Ray> rays = rays_of(workload::make_random_rays(around, 2000, 12, Mode::primary));
    // And rays through the degenerate triangles' own corners, along every axis.
    for (const Float3& v : source.scene.vertices())
        for (int k = 0; k < 3; ++k) {
            Ray r{v, -1.0f, Float3{0, 0, 0}, 1.0f};
            r.dir[k] = 1.0f;
            rays.push_back(r);
        }
    for (Mode mode : {Mode::primary, Mode::shadow}) {
        const workload::RaySet set = ray_set(rays, mode);
        for (const EngineUnderTest& e : engines) {
            std::size_t found = 0;
            if (mode == Mode::primary) {
                std::vector<Hit> hits;
                e.engine->intersect(set, hits, 1);
                for (const Hit& h : hits) found += h.hit();
            } else {
                std::vector<std::uint8_t> occluded;
                e.engine->occluded(set, occluded, 1);
                for (std::uint8_t o : occluded) found += o;
            }
            EXPECT_EQ(found, 0u) << source.name << ": " << e.name << " hit a degenerate triangle";
        }
    }
}

Scene slivers(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Soup s;
    for (int i = 0; i < 1500; ++i) {
        const Float3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
        const Float3 mid = (a + b) * 0.5f;
        const float lift = std::pow(10.0f, -3.0f - 4.0f * u(rng));  // 1e-3 .. 1e-7 off the line
        switch (i % 3) {
            case 0:
                s.add(a, b, mid + Float3{lift, -lift, lift});
                break;  // sliver (almost collinear)
            case 1:
                s.add(a, a + Float3{lift, 0, 0}, b);
                break;  // needle (one tiny edge)
            default:
                s.add(a, b, a + (b - a) * 0.25f + Float3{0, lift, 0});
                break;  // flat wedge
        }
    }
    return s.scene();
}

Scene with_degenerates(const Scene& base) {
    std::vector<Float3> v(base.vertices().begin(), base.vertices().end());
    std::vector<std::uint32_t> idx(base.indices().begin(), base.indices().end());
    const std::size_t n = base.triangle_count();
    for (std::size_t t = 0; t < n; t += 3) {
        const std::uint32_t a = idx[3 * t], b = idx[3 * t + 1];
        idx.insert(idx.end(), {a, a, b});  // a repeated corner
        const auto m = std::uint32_t(v.size());
        v.push_back((v[a] + v[b]) * 0.5f);  // a corner on the edge: collinear
        idx.insert(idx.end(), {a, m, b});
        idx.insert(idx.end(), {a, a, a});  // a point
    }
    return Scene(v, idx);
}

Scene duplicated(const Scene& base) {
    std::vector<std::uint32_t> idx(base.indices().begin(), base.indices().end());
    const std::size_t n = idx.size();
    for (std::size_t i = 0; i < n; i += 3) {
        idx.insert(idx.end(), {idx[i], idx[i + 1], idx[i + 2]});  // the same triangle again
        idx.insert(idx.end(), {idx[i], idx[i + 2], idx[i + 1]});  // and facing the other way
    }
    return Scene(base.vertices(), idx);
}

Scene in_one_point(Float3 p, int triangles) {
    const std::vector<Float3> v = {p, p, p};
    std::vector<std::uint32_t> idx;
    for (int i = 0; i < triangles; ++i) idx.insert(idx.end(), {0, 1, 2});
    return Scene(v, idx);
}

Scene on_one_line(int triangles) {
    std::vector<Float3> v;
    std::vector<std::uint32_t> idx;
    for (int i = 0; i < triangles; ++i) {
        const float x = float(i) / float(triangles);
        const auto b = std::uint32_t(v.size());
        v.insert(v.end(), {{x, 2 * x, -x}, {x + 0.5f, 2 * x + 1.0f, -x - 0.5f}, {x + 0.25f, 2 * x + 0.5f, -x - 0.25f}});
        idx.insert(idx.end(), {b, b + 1, b + 2});
    }
    return Scene(v, idx);
}

}  // namespace

TEST(Robust, DegenerateSceneSliversAndNeedles) { expect_clean(source_of("slivers", slivers(1))); }

TEST(Robust, DegenerateSceneZeroAreaTrianglesMixedIn) {
    const Scene s = with_degenerates(scenes::load_scene("tetra:3").scene);
    EXPECT_GT(s.degenerate_count(), 0u);
    expect_clean(source_of("tetra:3 with zero-area triangles", s));
}

TEST(Robust, DegenerateSceneCoincidentDuplicates) {
    expect_clean(source_of("tetra:3 tripled", duplicated(scenes::load_scene("tetra:3").scene)));
    expect_clean(source_of("sphereflake:0 tripled", duplicated(scenes::load_scene("sphereflake:0").scene)));
}

TEST(Robust, DegenerateSceneSingleFlatPlane) {
    const scenes::SceneSource plane = source_of("single plane", single_plane(24));
    expect_clean(plane);
    // Rays inside the plane itself and crossing it at every angle down to 1e-7.
    const auto engines = build_engines(plane.scene, fields());
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(-0.2f, 1.2f);
    std::vector<Ray> rays;
    for (int i = 0; i < 2000; ++i) {
        const float z = 0.5f + (i % 4 == 0 ? 0.0f : (i % 4 == 1 ? 1e-7f : 0.3f));
        const float dz = i % 2 ? 0.0f : -std::pow(10.0f, -float(i % 8));
        rays.push_back(Ray{{u(rng), u(rng), z}, 0.0f, {u(rng) - 0.5f, u(rng) - 0.5f, dz}, kInfinity});
    }
    for (Mode mode : {Mode::primary, Mode::shadow}) {
        std::vector<Ray> r = rays;
        if (mode == Mode::shadow)
            for (Ray& s : r) s.tfar = 2.0f;
        expect_exact_engines_clean(check_engines(engines, workload_for(plane, ray_set(r, mode)),
                                                 "single plane, grazing " + std::string(workload::to_string(mode)),
                                                 true));
    }
}

TEST(Robust, DegenerateSceneEverythingInOnePoint) {
    expect_nothing_to_hit(source_of("100 triangles in one point", in_one_point({0.5f, 0.25f, -3.0f}, 100)));
    expect_nothing_to_hit(source_of("one triangle in the origin", in_one_point({0.0f, 0.0f, 0.0f}, 1)));
    expect_nothing_to_hit(source_of("500 triangles on one line", on_one_line(500)));
}

TEST(Robust, DegenerateSceneSingleTriangle) {
    const std::vector<Float3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const std::vector<std::uint32_t> idx = {0, 1, 2};
    expect_clean(source_of("one triangle", Scene(v, idx)));
}

// Corners near float's largest value: the scene's box has an extent (and a diagonal) that overflows
// to infinity. Builders must not crash or hang and queries must report only real hits.
TEST(Robust, DegenerateSceneCoordinatesNearFloatMax) {
    for (float big : {1e37f, 1.7e38f, FLT_MAX}) {
        const std::vector<Float3> v = {{-big, -big, 0}, {big, -big, 0}, {0, big, 0}, {-big, -big, big}};
        const std::vector<std::uint32_t> idx = {0, 1, 2, 0, 1, 3, 1, 2, 3, 2, 0, 3};
        const Scene scene(v, idx);
        const auto engines = build_engines(scene, fields());
        std::vector<Ray> rays;
        for (float x : {-0.5f, 0.0f, 0.25f})
            for (float y : {-0.5f, 0.0f, 0.5f})
                rays.push_back(Ray{{x * big, y * big, -big}, 0.0f, {0, 0, 1}, kInfinity});
        const workload::RaySet set = ray_set(rays, Mode::primary);
        for (const EngineUnderTest& e : engines) {
            std::vector<Hit> hits;
            e.engine->intersect(set, hits, 1);
            std::size_t found = 0, exact = 0;
            for (const Hit& h : hits) found += h.hit();
            for (const Ray& r : rays) exact += exact_intersect(scene, r).hit();
            std::printf("[corners at %g] %-8s %zu of %zu rays hit (exact geometry: %zu)\n", double(big), e.name.c_str(),
                        found, rays.size(), exact);
            for (std::size_t i = 0; i < rays.size(); ++i) {
                const Hit& h = hits[i];
                if (!h.hit()) continue;  // beyond float's range hits may be lost (docs/robustness.md)
                ASSERT_LT(h.triangle, scene.triangle_count()) << e.name;
                EXPECT_TRUE(exact_intersect(scene, rays[i], 1e-6).hit())
                    << "big " << big << ": " << e.name << " reports a hit the ray does not have, ray " << i;
            }
        }
    }
}

}  // namespace beamtrace::test
