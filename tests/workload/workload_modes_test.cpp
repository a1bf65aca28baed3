// The workloads beyond camera rays, AO and one shadow light: diffuse bounce rays, shadow rays to
// several lights or to an area light, rays in a shuffled order; the options that do not go together;
// every engine on each of them against the oracle.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <tuple>

#include "beamtrace/error.hpp"
#include "experiments/bench_run.hpp"
#include "rays/ray_set.hpp"
#include "rays/workload.hpp"
#include "scenes/scene_source.hpp"

using namespace beamtrace;
using namespace beamtrace::workload;

namespace {

// A 2 x 2 square in the plane z = 0 (geometric normal +z), seen from z = -3 (from behind its normal):
// every pixel of a 30-degree view hits it.
scenes::SceneSource quad_scene() {
    const std::vector<Float3> v = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    const std::vector<std::uint32_t> i = {0, 1, 2, 0, 2, 3};
    scenes::Camera camera;
    camera.eye = {0, 0, -3};
    camera.at = {0, 0, 0};
    camera.fovy_degrees = 30;
    return scenes::SceneSource{"quad", Scene(std::span<const Float3>(v), std::span<const std::uint32_t>(i)), camera,
                               "a square"};
}

Workload make(const std::string& scene, Mode mode, int size, Order order = Order::input, int lights = 0,
              bool area = false) {
    WorkloadConfig config;
    config.scene = scene;
    config.mode = mode;
    config.width = config.height = size;
    config.ao_rays = 4;
    config.lights = lights;
    config.area_light = area;
    config.order = order;
    return make_workload(config);
}

// The primary slot of each pixel.
std::map<std::uint32_t, std::size_t> primary_slots(const Workload& w) {
    std::map<std::uint32_t, std::size_t> slots;
    for (std::size_t slot = 0; slot < w.primary.slots(); ++slot)
        if (w.primary.active(slot)) slots[w.primary.pixel[slot]] = slot;
    return slots;
}

std::size_t primary_hit_count(const Workload& w) {
    std::size_t n = 0;
    for (std::size_t slot = 0; slot < w.primary.slots(); ++slot)
        n += w.primary.active(slot) && w.primary_hits[slot].hit();
    return n;
}

// A ray, its pixel and the oracle's answer, as bits (for comparing multisets exactly).
using RayRecord = std::array<std::uint32_t, 12>;
std::uint32_t bits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}
std::vector<RayRecord> records(const Workload& w) {
    std::vector<RayRecord> out;
    for (std::size_t slot = 0; slot < w.rays.slots(); ++slot) {
        if (!w.rays.active(slot)) continue;
        const Ray r = w.rays.ray(slot);
        std::uint32_t answer = 0, t = 0;
        if (closest_hit(w.mode)) {
            answer = w.reference_hits[slot].triangle;
            t = bits(w.reference_hits[slot].t);
        } else {
            answer = w.reference_occluded[slot];
        }
        out.push_back({bits(r.org.x), bits(r.org.y), bits(r.org.z), bits(r.dir.x), bits(r.dir.y), bits(r.dir.z),
                       bits(r.tnear), bits(r.tfar), w.rays.pixel[slot], answer, t, 0});
    }
    return out;
}

bool same_rays(const RaySet& a, const RaySet& b) {
    if (a.slots() != b.slots() || a.ray_count != b.ray_count || a.pixel != b.pixel) return false;
    for (std::size_t slot = 0; slot < a.slots(); ++slot) {
        if (a.active(slot) != b.active(slot)) return false;
        if (!a.active(slot)) continue;
        const Ray x = a.ray(slot), y = b.ray(slot);
        if (!(x.org == y.org && x.dir == y.dir && x.tnear == y.tnear && x.tfar == y.tfar)) return false;
    }
    return true;
}

bool inside(const Box& box, Float3 p, float eps) {
    for (int k = 0; k < 3; ++k)
        if (p[k] < box.lower[k] - eps || p[k] > box.upper[k] + eps) return false;
    return true;
}

}  // namespace

TEST(WorkloadModes, ClosestHitModes) {
    EXPECT_TRUE(closest_hit(Mode::primary));
    EXPECT_TRUE(closest_hit(Mode::diffuse));
    EXPECT_FALSE(closest_hit(Mode::shadow));
    EXPECT_FALSE(closest_hit(Mode::ao));
    EXPECT_EQ(parse_mode("diffuse"), Mode::diffuse);
    EXPECT_EQ(parse_order("input"), Order::input);
    EXPECT_EQ(parse_order("shuffled"), Order::shuffled);
    try {
        parse_order("random");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("'random'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("input or shuffled"), std::string::npos) << e.what();
    }
}

TEST(WorkloadModes, DiffuseRaysAreCosineDistributedOverTheViewersHemisphereAndUnbounded) {
    WorkloadConfig config;
    config.mode = Mode::diffuse;
    config.width = config.height = 64;
    const Workload w = make_workload(quad_scene(), config);
    ASSERT_EQ(primary_hit_count(w), 64u * 64u) << "every pixel sees the square";
    ASSERT_EQ(w.rays.ray_count, 64u * 64u);
    EXPECT_EQ(w.rays.packets_x, 0);
    // Closest hits from the oracle (nothing to hit behind a lone square: all escape).
    EXPECT_EQ(w.reference_hits.size(), w.rays.slots());
    EXPECT_TRUE(w.reference_occluded.empty());
    const float offset = surface_offset(w.source.scene);
    std::array<int, 4> cos2_bins{}, quadrants{};
    double mean_cos = 0.0;
    std::set<std::uint32_t> pixels;
    for (std::size_t slot = 0; slot < w.rays.slots(); ++slot) {
        if (!w.rays.active(slot)) continue;
        const Ray r = w.rays.ray(slot);
        EXPECT_EQ(r.tnear, 0.0f);
        EXPECT_EQ(r.tfar, kInfinity);
        EXPECT_NEAR(length(r.dir), 1.0f, 1e-5f);
        // The normal turned towards the viewer is -z: the rays leave on the camera's side, from the
        // surface lifted by the offset.
        const float cos_theta = -r.dir.z;
        ASSERT_GT(cos_theta, 0.0f) << slot;
        EXPECT_NEAR(r.org.z, -offset, 1e-6f);
        EXPECT_TRUE(pixels.insert(w.rays.pixel[slot]).second) << "one ray per pixel";
        mean_cos += cos_theta;
        cos2_bins[std::min(3, int(cos_theta * cos_theta * 4.0f))]++;  // cos^2 is uniform for a cosine density
        quadrants[(r.dir.x >= 0.0f ? 1 : 0) + (r.dir.y >= 0.0f ? 2 : 0)]++;
    }
    mean_cos /= double(w.rays.ray_count);
    EXPECT_NEAR(mean_cos, 2.0 / 3.0, 0.02);
    for (int b = 0; b < 4; ++b) {
        EXPECT_NEAR(cos2_bins[std::size_t(b)], 1024, 130) << "cos^2 bin " << b;
        EXPECT_NEAR(quadrants[std::size_t(b)], 1024, 130) << "azimuth quadrant " << b;
    }
    // Deterministic per pixel.
    const Workload again = make_workload(quad_scene(), config);
    EXPECT_TRUE(same_rays(again.rays, w.rays));
}

TEST(WorkloadModes, DiffuseRaysLeaveFromTheirPixelsHitAndAreAnsweredAsClosestHits) {
    const Workload w = make("tetra:3", Mode::diffuse, 32);
    ASSERT_EQ(w.rays.ray_count, primary_hit_count(w));
    const auto slots = primary_slots(w);
    std::size_t hits = 0;
    for (std::size_t slot = 0; slot < w.rays.slots(); ++slot) {
        if (!w.rays.active(slot)) continue;
        const std::size_t p = slots.at(w.rays.pixel[slot]);
        const SurfacePoint s = surface_point(w.source.scene, w.primary.ray(p), w.primary_hits[p]);
        const Ray r = w.rays.ray(slot);
        EXPECT_GT(dot(r.dir, s.normal), 0.0f);
        EXPECT_LT(length(r.org - s.position), 2.0f * surface_offset(w.source.scene));
        hits += w.reference_hits[slot].hit();
    }
    EXPECT_GT(hits, 0u) << "some bounce rays hit the tetrahedra";
}

TEST(WorkloadModes, TheUpperBoxIsTheTopSlabAlongUpShrunkInwards) {
    const Box room{{0, 0, 0}, {12, 3.2f, 9}};
    const UpperBox u = upper_box(room, {0, 1, 0});
    EXPECT_EQ(u.up_axis, 1);
    EXPECT_EQ(u.up_sign, 1.0f);
    const Float3 lo{0.6f, 2.56f, 0.45f}, hi{11.4f, 3.04f, 8.55f};
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(u.box.lower[k], lo[k], 1e-5f) << k;
        EXPECT_NEAR(u.box.upper[k], hi[k], 1e-5f) << k;
    }
    // Up along -y, tilted: the bottom slab. Up along z: the z slab. A tie: y.
    const UpperBox down = upper_box(room, {0.1f, -0.9f, 0.2f});
    EXPECT_EQ(down.up_axis, 1);
    EXPECT_EQ(down.up_sign, -1.0f);
    EXPECT_NEAR(down.box.lower.y, 0.16f, 1e-5f);
    EXPECT_NEAR(down.box.upper.y, 0.64f, 1e-5f);
    EXPECT_EQ(upper_box(room, {0, 0, 2}).up_axis, 2);
    EXPECT_NEAR(upper_box(room, {0, 0, 2}).box.lower.z, 7.2f, 1e-5f);
    EXPECT_EQ(upper_box(room, {1, 1, 0}).up_axis, 1);
    EXPECT_THROW(upper_box(Box{}, {0, 1, 0}), Error);
}

TEST(WorkloadModes, LightsAreSpreadInsideTheUpperBox) {
    const UpperBox u = upper_box(Box{{-1, -2, -3}, {4, 5, 6}}, {0, 1, 0});
    const std::vector<Float3> lights = spread_lights(u, 64);
    ASSERT_EQ(lights.size(), 64u);
    Box spanned;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        EXPECT_TRUE(inside(u.box, lights[i], 0.0f)) << i;
        spanned.extend(lights[i]);
        for (std::size_t j = 0; j < i; ++j) EXPECT_FALSE(lights[i] == lights[j]) << i << " " << j;
    }
    for (int k = 0; k < 3; ++k)  // spread over the whole box, not bunched
        EXPECT_GT(spanned.extent()[k], 0.8f * u.box.extent()[k]) << k;
    EXPECT_EQ(spread_lights(u, 5)[3], lights[3]) << "light i does not depend on the count";
    // The first light: Halton point 1 = (1/2, 1/3, 1/5) across x, z and along y.
    EXPECT_NEAR(lights[0].x, u.box.lower.x + 0.5f * u.box.extent().x, 1e-5f);
    EXPECT_NEAR(lights[0].z, u.box.lower.z + u.box.extent().z / 3.0f, 1e-5f);
    EXPECT_NEAR(lights[0].y, u.box.lower.y + 0.2f * u.box.extent().y, 1e-5f);
    EXPECT_THROW(spread_lights(u, 0), Error);
}

TEST(WorkloadModes, EachHitGetsOneRayPerLightInConsecutiveLanes) {
    for (int n : {4, 16}) {
        const Workload w = make("tetra:3", Mode::shadow, 32, Order::input, n);
        ASSERT_EQ(w.lights.points.size(), std::size_t(n));
        EXPECT_FALSE(w.lights.area);
        EXPECT_EQ(point_lights(w), n);
        const UpperBox u = upper_box(w.source.scene.bounds(), w.camera.up);
        for (const Float3& l : w.lights.points) EXPECT_TRUE(inside(u.box, l, 0.0f));
        const std::size_t hits = primary_hit_count(w);
        ASSERT_GT(hits, 0u);
        ASSERT_EQ(w.rays.ray_count, hits * std::size_t(n));
        EXPECT_EQ(w.rays.packets_x, 0);
        const float eps = 1e-4f * w.source.scene.bounds().diagonal();
        std::vector<std::size_t> active;
        for (std::size_t slot = 0; slot < w.rays.slots(); ++slot)
            if (w.rays.active(slot)) active.push_back(slot);
        std::set<std::uint32_t> pixels;
        for (std::size_t k = 0; k < active.size(); k += std::size_t(n)) {
            const std::uint32_t pixel = w.rays.pixel[active[k]];
            EXPECT_TRUE(pixels.insert(pixel).second) << "a pixel's rays are together";
            for (int i = 0; i < n; ++i) {
                const std::size_t slot = active[k + std::size_t(i)];
                if (i > 0) {
                    EXPECT_EQ(slot, active[k + std::size_t(i) - 1] + 1) << "consecutive lanes";
                }
                EXPECT_EQ(w.rays.pixel[slot], pixel);
                const Ray r = w.rays.ray(slot);
                EXPECT_LT(length(r.org + r.dir - w.lights.points[std::size_t(i)]), eps)
                    << "ray " << i << " to light " << i;
                EXPECT_FLOAT_EQ(r.tfar, 1.0f - 1e-4f);
            }
            if (n == 16) {
                EXPECT_EQ(active[k] % 16, 0u) << "16 rays of a pixel make one packet";
            }
        }
    }
}

TEST(WorkloadModes, AreaLightRaysEndOnTheQuad) {
    const Workload w = make("sphereflake:1", Mode::shadow, 32, Order::input, 0, true);
    ASSERT_TRUE(w.lights.area);
    EXPECT_EQ(point_lights(w), 0);
    const AreaLight& a = *w.lights.area;
    const UpperBox u = upper_box(w.source.scene.bounds(), w.camera.up);
    // Centred over the scene, on the upper box's top face, half the smaller extent across.
    EXPECT_NEAR(a.center.x, u.box.center().x, 1e-4f);
    EXPECT_NEAR(a.center.z, u.box.center().z, 1e-4f);
    EXPECT_NEAR(a.center.y, u.box.upper.y, 1e-4f);
    EXPECT_NEAR(a.side, 0.5f * std::min(u.box.extent().x, u.box.extent().z), 1e-5f);
    EXPECT_TRUE(inside(u.box, a.point(0, 0), 1e-5f));
    EXPECT_TRUE(inside(u.box, a.point(1, 1), 1e-5f));
    // Same slots as the primary rays: an image.
    EXPECT_EQ(w.rays.packets_x, w.primary.packets_x);
    ASSERT_EQ(w.rays.ray_count, primary_hit_count(w));
    const float eps = 1e-5f * w.source.scene.bounds().diagonal();
    std::set<std::tuple<float, float>> ends;
    for (std::size_t slot = 0; slot < w.rays.slots(); ++slot) {
        if (!w.rays.active(slot)) continue;
        EXPECT_EQ(w.rays.pixel[slot], w.primary.pixel[slot]);
        const Ray r = w.rays.ray(slot);
        const Float3 end = r.org + r.dir;
        EXPECT_NEAR(end.y, a.center.y, eps);
        EXPECT_LE(std::fabs(end.x - a.center.x), 0.5f * a.side + eps);
        EXPECT_LE(std::fabs(end.z - a.center.z), 0.5f * a.side + eps);
        EXPECT_FLOAT_EQ(r.tfar, 1.0f - 1e-4f);
        ends.emplace(end.x, end.z);
    }
    EXPECT_GT(ends.size(), w.rays.ray_count * 9 / 10) << "a point of its own for every pixel";
    const Workload again = make("sphereflake:1", Mode::shadow, 32, Order::input, 0, true);
    EXPECT_TRUE(same_rays(again.rays, w.rays));
}

TEST(WorkloadModes, ShuffledRaysAreAPermutationOfTheInputRays) {
    struct Case {
        Mode mode;
        int lights;
        bool area;
    };
    for (const Case c : {Case{Mode::primary, 0, false}, Case{Mode::shadow, 0, false}, Case{Mode::shadow, 3, false},
                         Case{Mode::shadow, 0, true}, Case{Mode::ao, 0, false}, Case{Mode::diffuse, 0, false}}) {
        const std::string what =
            std::string(to_string(c.mode)) + " lights " + std::to_string(c.lights) + (c.area ? " area" : "");
        const Workload in = make("tetra:3", c.mode, 24, Order::input, c.lights, c.area);
        const Workload sh = make("tetra:3", c.mode, 24, Order::shuffled, c.lights, c.area);
        EXPECT_EQ(sh.order, Order::shuffled);
        ASSERT_EQ(sh.rays.ray_count, in.rays.ray_count) << what;
        ASSERT_GT(sh.rays.ray_count, 16u) << what;
        EXPECT_EQ(sh.rays.packets_x, 0) << what;
        EXPECT_EQ(sh.rays.packets_y, 0) << what;
        EXPECT_EQ(sh.rays.packets.size(), (sh.rays.ray_count + 15) / 16) << what << ": repacked 16 to a packet";
        for (std::size_t slot = 0; slot < sh.rays.slots(); ++slot) {
            EXPECT_EQ(sh.rays.active(slot), slot < sh.rays.ray_count) << what;
            if (!sh.rays.active(slot)) {
                EXPECT_EQ(sh.rays.pixel[slot], kNoPixel) << what;
            }
        }
        // The same rays, each with its pixel and the oracle's answer.
        std::vector<RayRecord> a = records(in), b = records(sh);
        EXPECT_NE(a, b) << what << ": the order changed";
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        EXPECT_EQ(a, b) << what;
        // Deterministic, and reorder() of the input rays is the same permutation.
        const Workload again = make("tetra:3", c.mode, 24, Order::shuffled, c.lights, c.area);
        EXPECT_TRUE(same_rays(again.rays, sh.rays)) << what;
        EXPECT_TRUE(same_rays(reorder(in.rays, Order::shuffled), sh.rays)) << what;
        EXPECT_TRUE(same_rays(reorder(in.rays, Order::input), in.rays)) << what;
    }
}

TEST(WorkloadModes, OptionsThatDoNotGoTogetherAreNamed) {
    const auto message = [](const WorkloadConfig& c) {
        try {
            c.validate();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    WorkloadConfig c;
    c.scene = "tetra:1";
    c.mode = Mode::shadow;
    EXPECT_EQ(message(c), "");
    c.lights = 4;
    EXPECT_EQ(message(c), "");
    c.light = Float3{1, 2, 3};
    EXPECT_NE(message(c).find("--lights and --light cannot be used together"), std::string::npos) << message(c);
    EXPECT_THROW(make_workload(c), Error);
    c.light.reset();
    c.area_light = true;
    EXPECT_NE(message(c).find("--area-light and --lights cannot be used together"), std::string::npos) << message(c);
    c.lights = 0;
    EXPECT_EQ(message(c), "");
    c.light = Float3{1, 2, 3};
    EXPECT_NE(message(c).find("--area-light and --light cannot be used together"), std::string::npos) << message(c);
    c.light.reset();
    c.mode = Mode::ao;
    EXPECT_NE(message(c).find("--area-light applies to shadow rays only"), std::string::npos) << message(c);
    c.area_light = false;
    c.lights = 2;
    c.mode = Mode::diffuse;
    EXPECT_NE(message(c).find("--lights applies to shadow rays only"), std::string::npos) << message(c);
    c.mode = Mode::shadow;
    c.lights = 5000;
    EXPECT_NE(message(c).find("--lights must be between 1 and 4096"), std::string::npos) << message(c);
}

TEST(WorkloadModes, EveryEngineAnswersEveryNewWorkloadExactly) {
    const scenes::SceneSource source = scenes::load_scene("tetra:3");
    std::vector<std::unique_ptr<Engine>> engines;
    for (const char* name : {"kd1", "kd16", "mlrta", "vlf", "brute", "embree1", "embree16", "embree-stream"}) {
        engines.push_back(make_engine(name));
        engines.back()->build(source.scene, EngineOptions{});
    }
    struct Case {
        Mode mode;
        int lights;
        bool area;
    };
    for (const Case c : {Case{Mode::primary, 0, false}, Case{Mode::diffuse, 0, false}, Case{Mode::shadow, 4, false},
                         Case{Mode::shadow, 0, true}, Case{Mode::ao, 0, false}})
        for (Order order : {Order::input, Order::shuffled}) {
            WorkloadConfig config;
            config.mode = c.mode;
            config.width = config.height = 24;
            config.ao_rays = 4;
            config.lights = c.lights;
            config.area_light = c.area;
            config.order = order;
            const Workload w = make_workload(source, config);
            const std::string what = describe_rays(c.mode, order, point_lights(w), c.area);
            for (const auto& e : engines) {
                const oracle::Tally t = check_against_oracle(*e, w, 2);
                EXPECT_EQ(t.total(), w.rays.ray_count) << e->name() << " " << what;
                EXPECT_EQ(t.mismatch, 0u) << e->name() << " " << what;
            }
        }
}

TEST(WorkloadModes, BenchResultsNameTheWorkload) {
    WorkloadConfig config;
    config.scene = "tetra:2";
    config.mode = Mode::shadow;
    config.width = config.height = 16;
    config.lights = 3;
    config.order = Order::shuffled;
    BenchOptions options;
    options.engines = {"kd1"};
    options.repeats = 1;
    options.anchor_engines = false;
    const nlohmann::json j = to_json(run_bench(make_workload(config), options));
    EXPECT_EQ(j["mode"], "shadow");
    EXPECT_EQ(j["order"], "shuffled");
    EXPECT_EQ(j["lights"], 3);
    EXPECT_EQ(j["area_light"], false);
    EXPECT_EQ(j["engines"]["kd1"]["oracle"]["mismatch"], 0);
    EXPECT_EQ(describe_rays(Mode::shadow, Order::shuffled, 3, false), "mode shadow (3 lights), order shuffled");
    EXPECT_EQ(describe_rays(Mode::shadow, Order::input, 0, true), "mode shadow (area light), order input");
    EXPECT_EQ(describe_rays(Mode::diffuse, Order::input, 0, false), "mode diffuse, order input");
}
