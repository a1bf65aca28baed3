// Extremes.Scale*: the same scenes and the same rays scaled by 1e-6 .. 1e6, moved 1e5 from the
// origin, and beyond the range where Embree stays consistent. Every exact engine must agree with
// exact geometry (zero `mismatch`) and with Embree wherever Embree itself agrees with exact
// geometry. Where float32 runs out (coordinates of 1e-20 and 1e20, or 1e8 from the origin), the
// engines must still agree with each other bit for bit and may lose hits but never invent one.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "extremes/engine_checks.hpp"
#include "extremes/exact_reference.hpp"
#include "extremes/placement.hpp"
#include "rays/workload.hpp"

namespace beamtrace::test {
namespace {

using workload::Mode;

// The rays of one scene at scale 1: primary, shadow and ao rays of its camera (an image, so MLRTA
// traces tiles of beams), and incoherent random rays (closest hit and occlusion).
std::vector<std::pair<std::string, workload::RaySet>> unit_rays(const scenes::SceneSource& source) {
    std::vector<std::pair<std::string, workload::RaySet>> sets;
    for (Mode mode : {Mode::primary, Mode::shadow, Mode::ao}) {
        workload::WorkloadConfig config;
        config.mode = mode;
        config.width = config.height = mode == Mode::ao ? 24 : 48;
        config.ao_rays = 4;
        sets.emplace_back(workload::to_string(mode), workload::make_workload(source, config).rays);
    }
    sets.emplace_back("random primary", workload::make_random_rays(source.scene.bounds(), 2000, 5, Mode::primary));
    sets.emplace_back("random shadow", workload::make_random_rays(source.scene.bounds(), 2000, 6, Mode::shadow));
    return sets;
}

EngineChoice small_fields() {
    EngineChoice choice;
    choice.options.vlf.directions = 129;
    choice.options.vlf.tiles = 32;
    return choice;
}

constexpr const char* kScenes[] = {"tetra:4", "sphereflake:1"};

// Every scene and ray set at one placement, checked against Embree and exact geometry.
void expect_clean_at(const Placement& placement) {
    for (const char* spec : kScenes) {
        const scenes::SceneSource unit = scenes::load_scene(spec);
        const scenes::SceneSource source = placed(unit, placement);
        const std::vector<EngineUnderTest> engines = build_engines(source.scene, small_fields());
        for (const auto& [name, rays] : unit_rays(unit))
            expect_exact_engines_clean(
                check_engines(engines, workload_for(source, placed(rays, placement)), source.name + " " + name, true));
    }
}

Placement scaled(double s) {
    Placement p;
    p.scale = s;
    return p;
}

Placement unit_directions(Placement p) {
    p.unit_directions = true;
    return p;
}

Placement moved(double distance) {
    Placement p;
    p.offset[0] = distance;
    p.offset[1] = -distance;
    p.offset[2] = distance;
    return p;
}

// Whether the ray really crosses the triangle near parameter t (double precision, relative 1e-4).
bool real_hit(const Scene& scene, const Ray& ray, const Hit& h) {
    if (!h.hit() || h.triangle >= scene.triangle_count() || scene.is_degenerate(h.triangle)) return false;
    Ray near = ray;
    const double slack = 1e-4 * std::max(1.0, std::fabs(double(h.t)));
    near.tnear = float(std::max(double(ray.tnear), double(h.t) - slack));
    near.tfar = float(std::min(double(ray.tfar), double(h.t) + slack));
    // Only this triangle: a scene of it alone.
    const Triangle& t = scene.triangle(h.triangle);
    const Float3 corners[3] = {t.v0, t.v1, t.v2};
    const std::uint32_t ids[3] = {0, 1, 2};
    return exact_intersect(Scene(std::span<const Float3>(corners), std::span<const std::uint32_t>(ids)), near).hit();
}

struct FloatLimitRecord {
    std::uint64_t rays = 0, hits = 0;  // rays, and rays exact geometry finds a hit (or an occluder) for
    std::uint64_t lost = 0;            // over every exact engine: geometry hits, the engine does not
    std::uint64_t wrong = 0;           // the engine hits what the ray does not cross (or not there)
};

// Beyond float's range: traces every ray set with every exact engine and counts, against exact
// geometry, the hits lost and the wrong ones. Every reported triangle must be a real, hittable one.
FloatLimitRecord check_float_limit(const Placement& placement) {
    FloatLimitRecord record;
    for (const char* spec : kScenes) {
        const scenes::SceneSource unit = scenes::load_scene(spec);
        const scenes::SceneSource source = placed(unit, placement);
        const Scene& scene = source.scene;
        EngineChoice choice = small_fields();
        choice.brute = false;  // denormal arithmetic makes it a hundred times slower at 1e-20
        choice.vlf_fast = false;
        const std::vector<EngineUnderTest> engines = build_engines(scene, choice);
        for (const auto& [name, unit_set] : unit_rays(unit)) {
            const workload::RaySet rays = placed(unit_set, placement);
            const bool closest = closest_hit(rays.mode);
            std::vector<Hit> exact(rays.slots());
            std::vector<std::uint8_t> exact_blocked(rays.slots(), 0);
            for (std::size_t slot = 0; slot < rays.slots(); ++slot) {
                if (!rays.active(slot)) continue;
                ++record.rays;
                if (closest)
                    exact[slot] = exact_intersect(scene, rays.ray(slot));
                else
                    exact_blocked[slot] = exact_occluded(scene, rays.ray(slot));
                record.hits += closest ? exact[slot].hit() : exact_blocked[slot];
            }
            for (const EngineUnderTest& e : engines) {
                std::vector<Hit> hits;
                std::vector<std::uint8_t> occluded;
                if (closest)
                    e.engine->intersect(rays, hits, 1);
                else
                    e.engine->occluded(rays, occluded, 1);
                for (std::size_t slot = 0; slot < rays.slots(); ++slot) {
                    if (!rays.active(slot)) continue;
                    if (!closest) {
                        record.lost += exact_blocked[slot] && !occluded[slot];
                        record.wrong += !exact_blocked[slot] && occluded[slot];
                        continue;
                    }
                    const Hit& h = hits[slot];
                    if (h.hit()) {
                        EXPECT_TRUE(h.triangle < scene.triangle_count() && !scene.is_degenerate(h.triangle))
                            << source.name << " " << name << ": " << e.name << " hit triangle " << h.triangle;
                    }
                    record.lost += exact[slot].hit() && !h.hit();
                    record.wrong += h.hit() && !real_hit(scene, rays.ray(slot), h);
                }
            }
        }
    }
    return record;
}

// Each scale twice: directions scaled with the scene (t unchanged) and unit directions (t scaled).
void expect_clean_at_scale(double s) {
    expect_clean_at(scaled(s));
    expect_clean_at(unit_directions(scaled(s)));
}

}  // namespace

TEST(Extremes, ScaleMicro) { expect_clean_at_scale(1e-6); }
TEST(Extremes, ScaleMilli) { expect_clean_at_scale(1e-3); }
TEST(Extremes, ScaleOne) { expect_clean_at_scale(1.0); }
TEST(Extremes, ScaleKilo) { expect_clean_at_scale(1e3); }
TEST(Extremes, ScaleMega) { expect_clean_at_scale(1e6); }
TEST(Extremes, ScaleFarFromOrigin) {
    expect_clean_at(moved(1e5));
    expect_clean_at(unit_directions(moved(1e5)));
}

// The edges of the range where every exact engine still equals exact geometry (docs/robustness.md):
// 1e-17 to 1e17 when directions scale with the scene, 1e-13 to 1e13 with unit directions (t then
// grows with the scene, and t * |dir| * |corner|^2 must stay inside float's range). Embree has
// mismatches of its own at 1e-17 and 1e17 (from about 1e-12 and 1e13 with scaled directions).
TEST(Extremes, ScaleEdgesOfTheFloatRange) {
    expect_clean_at(scaled(1e-17));
    expect_clean_at(scaled(1e17));
    expect_clean_at(unit_directions(scaled(1e-13)));
    expect_clean_at(unit_directions(scaled(1e13)));
}

// Where float32 runs out: products of two coordinates (1e-40 at scale 1e-20) fall below float's
// normal range and hits are lost; at 1e20 they overflow; with unit directions the same happens from
// about 1e-16 and 1e15. 1e8 from the origin, a scene of size 2 collapses onto float's grid of
// spacing 8. Documented behaviour: no crash, every exact engine answers exactly as kd1, hits may be
// lost but are never invented.
TEST(Extremes, ScaleWhereFloatRunsOut) {
    const std::pair<const char*, Placement> cases[] = {
        {"scale 1e-20", scaled(1e-20)},
        {"scale 1e20", scaled(1e20)},
        {"scale 1e-16, unit directions", unit_directions(scaled(1e-16))},
        {"scale 1e15, unit directions", unit_directions(scaled(1e15))},
        {"moved 1e8", moved(1e8)},
    };
    std::vector<FloatLimitRecord> records;
    for (const auto& [what, placement] : cases) {
        records.push_back(check_float_limit(placement));
        const FloatLimitRecord& r = records.back();
        std::printf("%s: %llu rays, %llu with a hit; over the exact engines %llu hits lost, %llu wrong\n", what,
                    (unsigned long long)r.rays, (unsigned long long)r.hits, (unsigned long long)r.lost,
                    (unsigned long long)r.wrong);
    }
    // What docs/robustness.md states. At 1e-20 every hit is lost (with the paper's minimum tile of
    // one packet MLRTA kept one AO hit; with the default tiles of 2x2 packets and more it does not)
    // and none is wrong; far from the origin the collapsed scene is traced exactly. If these change,
    // the range changed: update the doc.
    constexpr std::uint64_t kExactEngines = 9;  // kd1, kd16, mlrta, vlf, stream, raycls, crsh, rah, lists
    EXPECT_EQ(records[0].lost, kExactEngines * records[0].hits);
    EXPECT_EQ(records[0].wrong, 0u);
    EXPECT_GT(records[1].lost + records[1].wrong, 0u);
    EXPECT_GT(records[2].lost + records[2].wrong, 0u);
    EXPECT_GT(records[3].lost + records[3].wrong, 0u);
    EXPECT_EQ(records[4].lost, 0u);
    EXPECT_EQ(records[4].wrong, 0u);
}

}  // namespace beamtrace::test
