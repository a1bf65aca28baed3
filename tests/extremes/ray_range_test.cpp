// Robust.RayRange*: where rays start and end. Rays starting exactly on a surface (tnear = 0 and a
// small epsilon), empty segments (tfar = tnear), reversed ones (tnear > tfar, inactive), tfar =
// +inf and FLT_MAX, segments reaching far behind the origin, huge and tiny t (directions of length
// 1e-30 and 1e30), and rays that describe no segment at all (NaN, infinite or zero components):
// those report no hit and are never occluded in every engine (the contract of beamtrace/ray.hpp).
#include <gtest/gtest.h>

#include <cfloat>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <limits>
#include <random>

#include "extremes/engine_checks.hpp"
#include "extremes/exact_reference.hpp"
#include "support/differential.hpp"
#include "rays/ray_set.hpp"

namespace beamtrace::test {
namespace {

using workload::Mode;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

EngineChoice fields() {
    EngineChoice choice;
    choice.options.vlf.directions = 129;
    choice.options.vlf.tiles = 32;
    return choice;
}

Float3 random_unit(std::mt19937& rng) {
    std::normal_distribution<float> g;
    Float3 v;
    do v = Float3{g(rng), g(rng), g(rng)};
    while (dot(v, v) < 1e-4f);
    return normalize(v);
}

// Points exactly on surfaces: the oracle's hits of the scene camera's primary rays (rounded to float,
// so on the surface as near as float gets), each with a random direction.
std::vector<Ray> from_surfaces(const scenes::SceneSource& source, unsigned seed) {
    workload::WorkloadConfig config;
    config.width = config.height = 48;
    const workload::Workload w = workload::make_workload(source, config);
    std::mt19937 rng(seed);
    std::vector<Ray> rays;
    for (std::size_t slot = 0; slot < w.rays.slots(); ++slot) {
        if (!w.rays.active(slot) || !w.reference_hits[slot].hit()) continue;
        const Ray primary = w.rays.ray(slot);
        const workload::SurfacePoint p = workload::surface_point(source.scene, primary, w.reference_hits[slot]);
        rays.push_back(Ray{p.position, 0.0f, random_unit(rng), kInfinity});
    }
    return rays;
}

void check(const scenes::SceneSource& source, const std::vector<EngineUnderTest>& engines, const std::string& what,
           const std::vector<Ray>& rays, Mode mode, bool against_embree = true) {
    CaseReport r = check_engines(engines, workload_for(source, ray_set(rays, mode)), source.name + " " + what, true);
    if (!against_embree) {
        // Embree cannot take this range (see docs/robustness.md): exact geometry alone decides.
        print(r);
        for (const EngineReport& e : r.engines)
            if (e.exact) expect_no_mismatch(e.geometry.tally, r.what + " " + e.engine + " vs geometry");
        return;
    }
    expect_exact_engines_clean(r);
}

std::vector<scenes::SceneSource> range_scenes() {
    return {scenes::load_scene("tetra:4"), scenes::load_scene("sphereflake:1")};
}

std::vector<Ray> with(std::vector<Ray> rays, float tnear, float tfar) {
    for (Ray& r : rays) {
        r.tnear = tnear;
        r.tfar = tfar;
    }
    return rays;
}

}  // namespace

TEST(Robust, RayRangeStartOnSurface) {
    for (const scenes::SceneSource& s : range_scenes()) {
        const auto engines = build_engines(s.scene, fields());
        const std::vector<Ray> rays = from_surfaces(s, 1);
        const float eps = 1e-4f * s.scene.bounds().diagonal();
        for (Mode mode : {Mode::primary, Mode::shadow}) {
            const float tfar = mode == Mode::primary ? kInfinity : 0.5f * s.scene.bounds().diagonal();
            check(s, engines, "from the surface, tnear 0", with(rays, 0.0f, tfar), mode);
            check(s, engines, "from the surface, tnear eps", with(rays, eps, tfar), mode);
            check(s, engines, "from the surface, tnear -eps", with(rays, -eps, tfar), mode);
        }
    }
}

TEST(Robust, RayRangeEmptyAndReversedSegments) {
    for (const scenes::SceneSource& s : range_scenes()) {
        const auto engines = build_engines(s.scene, fields());
        const workload::RaySet random = workload::make_random_rays(s.scene.bounds(), 2000, 3, Mode::primary);
        std::vector<Ray> rays = rays_of(random);
        // tfar = tnear at a random distance, and exactly at exact geometry's hit.
        std::mt19937 rng(4);
        std::uniform_real_distribution<float> u(0.0f, s.scene.bounds().diagonal());
        std::vector<Ray> empty, at_hit, reversed;
        for (const Ray& r : rays) {
            const float t = u(rng);
            empty.push_back(Ray{r.org, t, r.dir, t});
            const Hit h = exact_intersect(s.scene, r);
            if (h.hit()) at_hit.push_back(Ray{r.org, h.t, r.dir, h.t});
            reversed.push_back(Ray{r.org, t, r.dir, std::nextafter(t, -kInfinity)});
            reversed.push_back(Ray{r.org, kInfinity, r.dir, t});
            reversed.push_back(Ray{r.org, 0.0f, r.dir, -kInfinity});
        }
        for (Mode mode : {Mode::primary, Mode::shadow}) {
            check(s, engines, "empty segments", empty, mode);
            check(s, engines, "empty segments at the hit", at_hit, mode);
        }
        // Reversed segments describe nothing: exactly no hit in every engine.
        const workload::RaySet set = ray_set(reversed, Mode::primary);
        for (const EngineUnderTest& e : engines) {
            std::vector<Hit> hits;
            std::vector<std::uint8_t> occluded;
            e.engine->intersect(set, hits, 1);
            workload::RaySet shadow = set;
            shadow.mode = Mode::shadow;
            e.engine->occluded(shadow, occluded, 1);
            std::size_t reported = 0;
            for (std::size_t slot = 0; slot < set.slots(); ++slot)
                reported += set.active(slot) && (hits[slot].hit() || occluded[slot]);
            EXPECT_EQ(reported, 0u) << s.name << ": " << e.name << " reports hits on reversed segments";
        }
    }
}

TEST(Robust, RayRangeInfiniteAndHugeT) {
    for (const scenes::SceneSource& s : range_scenes()) {
        const auto engines = build_engines(s.scene, fields());
        const std::vector<Ray> rays = rays_of(workload::make_random_rays(s.scene.bounds(), 2000, 5, Mode::primary));
        check(s, engines, "tfar FLT_MAX", with(rays, 0.0f, FLT_MAX), Mode::primary);
        check(s, engines, "tfar FLT_MAX", with(rays, 0.0f, FLT_MAX), Mode::shadow);
        check(s, engines, "tnear -1e3", with(rays, -1e3f, kInfinity), Mode::primary);
        check(s, engines, "tnear -1e3", with(rays, -1e3f, 1e3f), Mode::shadow);
        // Far behind the origin: Embree's moved origin would lie beyond its range (it reports nothing).
        check(s, engines, "tnear -1e30", with(rays, -1e30f, kInfinity), Mode::primary, false);
        check(s, engines, "tnear -1e30", with(rays, -1e30f, FLT_MAX), Mode::shadow, false);
        // Huge and tiny t: the same rays with directions of length 1e-30 and 1e30.
        for (float length : {1e-30f, 1e-20f, 1e20f, 1e30f}) {
            std::vector<Ray> scaled = rays;
            for (Ray& r : scaled) r.dir = r.dir * length;
            char what[64];
            std::snprintf(what, sizeof what, "direction length %g", double(length));
            check(s, engines, what, scaled, Mode::primary);
            for (Ray& r : scaled) r.tfar = 0.5f * s.scene.bounds().diagonal() / length;
            check(s, engines, what, scaled, Mode::shadow);
        }
    }
}

// Rays that describe no segment. The contract (beamtrace/ray.hpp): no hit, never occluded, in every
// engine and every entry point (single rays, packets, MLRTA grids); never a crash or a hang.
std::vector<Ray> ill_formed(const Box& b) {
    const Float3 org = b.center() + b.extent() * 0.01f;
    const Float3 dir{0.3f, -0.5f, 0.8f};
    const float inf = kInfinity;
    std::vector<Ray> rays = {
        {{kNaN, org.y, org.z}, 0.0f, dir, inf},
        {{org.x, kNaN, org.z}, 0.0f, dir, inf},
        {org, 0.0f, {kNaN, dir.y, dir.z}, inf},
        {org, 0.0f, {dir.x, dir.y, kNaN}, inf},
        {org, 0.0f, {kNaN, kNaN, kNaN}, inf},
        {{kNaN, kNaN, kNaN}, 0.0f, dir, inf},
        {org, kNaN, dir, inf},
        {org, 0.0f, dir, kNaN},
        {org, kNaN, dir, kNaN},
        {{inf, org.y, org.z}, 0.0f, dir, inf},
        {{org.x, -inf, org.z}, 0.0f, dir, inf},
        {org, 0.0f, {inf, dir.y, dir.z}, inf},
        {org, 0.0f, {dir.x, -inf, dir.z}, inf},
        {org, 0.0f, {inf, inf, inf}, inf},
        {org, 0.0f, {0.0f, 0.0f, 0.0f}, inf},
        {org, 0.0f, {-0.0f, 0.0f, -0.0f}, inf},
        {org, inf, dir, inf},
        {org, 0.0f, dir, -inf},
        {org, -inf, dir, inf},
        {org, -inf, dir, -inf},
        {{inf, inf, inf}, -inf, {-inf, kNaN, 0.0f}, kNaN},
    };
    // From outside the box too, aimed at it (a NaN must not slip through a box test).
    const Float3 out = b.lower - b.extent();
    rays.push_back({out, 0.0f, {kNaN, 1.0f, 1.0f}, inf});
    rays.push_back({out, kNaN, b.center() - out, inf});
    rays.push_back({out, 0.0f, b.center() - out, kNaN});
    return rays;
}

TEST(Robust, RayRangeIllFormedRaysReportNothing) {
    for (const scenes::SceneSource& s : range_scenes()) {
        const auto engines = build_engines(s.scene, fields());
        const std::vector<Ray> rays = ill_formed(s.scene.bounds());
        for (const Ray& r : rays) ASSERT_FALSE(well_formed(r));
        // Alone (one ray per packet) and all together.
        std::vector<workload::RaySet> sets;
        for (const Ray& r : rays) sets.push_back(ray_set({r}, Mode::primary));
        sets.push_back(ray_set(rays, Mode::primary));
        sets.push_back(image_ray_set(rays, 4, Mode::primary));
        for (workload::RaySet& set : sets) {
            for (const EngineUnderTest& e : engines) {
                const auto start = std::chrono::steady_clock::now();
                std::vector<Hit> hits;
                std::vector<std::uint8_t> occluded;
                e.engine->intersect(set, hits, 1);
                set.mode = Mode::shadow;
                e.engine->occluded(set, occluded, 1);
                set.mode = Mode::primary;
                for (std::size_t slot = 0; slot < set.slots(); ++slot) {
                    if (!set.active(slot)) continue;
                    const Ray r = set.ray(slot);
                    EXPECT_FALSE(hits[slot].hit())
                        << s.name << " " << e.name << ": ray " << slot << " org " << r.org.x << "," << r.org.y << ","
                        << r.org.z << " dir " << r.dir.x << "," << r.dir.y << "," << r.dir.z << " [" << r.tnear << ","
                        << r.tfar << "] hit triangle " << hits[slot].triangle;
                    EXPECT_FALSE(occluded[slot])
                        << s.name << " " << e.name << ": ray " << slot << " org " << r.org.x << "," << r.org.y << ","
                        << r.org.z << " dir " << r.dir.x << "," << r.dir.y << "," << r.dir.z << " [" << r.tnear << ","
                        << r.tfar << "] occluded";
                }
                const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                EXPECT_LT(seconds, 1.0) << s.name << " " << e.name << ": ill-formed rays are slow";
            }
        }
    }
}

}  // namespace beamtrace::test
