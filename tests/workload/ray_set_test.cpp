// Ray sets: layout of the packets, pixels of the lanes, secondary rays, determinism.
#include <gtest/gtest.h>

#include <set>

#include "beamtrace/error.hpp"
#include "scenes/scene_source.hpp"
#include "experiments/bench_run.hpp"
#include "rays/ray_set.hpp"

using namespace beamtrace;
using namespace beamtrace::workload;

TEST(RaySet, PrimaryRaysCoverEveryPixelOnce) {
    scenes::Camera cam;
    cam.eye = {0, 0, 5};
    cam.at = {0, 0, 0};
    const RaySet s = make_primary_rays(cam, 10, 7);  // partial 4x4 blocks at the edges
    EXPECT_EQ(s.ray_count, 70u);
    EXPECT_EQ(s.packets.size(), 3u * 2u);
    std::set<std::uint32_t> seen;
    for (std::size_t slot = 0; slot < s.slots(); ++slot) {
        if (!s.active(slot)) {
            EXPECT_EQ(s.pixel[slot], kNoPixel);
            continue;
        }
        EXPECT_TRUE(seen.insert(s.pixel[slot]).second);
        const std::uint32_t px = s.pixel[slot] % 10, py = s.pixel[slot] / 10;
        const Ray expected = cam.primary_ray(int(px), int(py), 10, 7);
        EXPECT_EQ(s.ray(slot).dir, expected.dir);
    }
    EXPECT_EQ(seen.size(), 70u);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(s.packets.data()) % 64, 0u) << "packets are 64-byte aligned";
}

TEST(RaySet, RejectsBadSizes) {
    scenes::Camera cam;
    cam.eye = {0, 0, 5};
    EXPECT_THROW(make_primary_rays(cam, 0, 10), Error);
    EXPECT_THROW(parse_mode("secondary"), Error);
    EXPECT_EQ(parse_mode("ao"), Mode::ao);
}

TEST(RaySet, SecondaryRaysStartAtPrimaryHits) {
    WorkloadConfig config;
    config.scene = "tetra:3";
    config.width = config.height = 32;
    config.mode = Mode::ao;
    config.ao_rays = 16;
    const Workload w = make_workload(config);
    std::size_t primary_hits = 0;
    for (const Hit& h : w.primary_hits) primary_hits += h.hit();
    ASSERT_GT(primary_hits, 0u);
    EXPECT_EQ(w.rays.ray_count, primary_hits * 16);
    const float length = 0.1f * w.source.scene.bounds().diagonal();
    for (std::size_t slot = 0; slot < w.rays.slots(); ++slot) {
        if (!w.rays.active(slot)) continue;
        const Ray r = w.rays.ray(slot);
        EXPECT_NEAR(beamtrace::length(r.dir), 1.0f, 1e-5f);
        EXPECT_FLOAT_EQ(r.tfar, length);
    }
    // The 16 rays of a pixel fill one packet.
    for (std::size_t p = 0; p < w.rays.packets.size(); ++p) {
        EXPECT_EQ(w.rays.packets[p].active, 0xFFFFu);
        for (int i = 1; i < 16; ++i) EXPECT_EQ(w.rays.pixel[p * 16 + i], w.rays.pixel[p * 16]);
    }
    const Workload again = make_workload(config);
    ASSERT_EQ(again.rays.slots(), w.rays.slots());
    for (std::size_t slot = 0; slot < w.rays.slots(); ++slot) {  // ray generation is deterministic
        ASSERT_EQ(again.rays.active(slot), w.rays.active(slot));
        const Ray a = again.rays.ray(slot), b = w.rays.ray(slot);
        ASSERT_TRUE(a.org == b.org && a.dir == b.dir && a.tnear == b.tnear && a.tfar == b.tfar) << slot;
    }
}

TEST(RaySet, ShadowRaysEndBeforeTheLight) {
    WorkloadConfig config;
    config.scene = "sphereflake:1";
    config.width = config.height = 16;
    config.mode = Mode::shadow;
    const Workload w = make_workload(config);
    ASSERT_GT(w.rays.ray_count, 0u);
    for (std::size_t slot = 0; slot < w.rays.slots(); ++slot) {
        if (!w.rays.active(slot)) continue;
        const Ray r = w.rays.ray(slot);
        const Float3 end = r.org + r.dir;
        EXPECT_NEAR(end.x, w.light.x, 1e-3f);
        EXPECT_LT(r.tfar, 1.0f);
    }
}

TEST(Engines, UnknownEngineIsNamed) {
    try {
        make_engine("optix");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("optix"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("kd1"), std::string::npos);
    }
}

TEST(Engines, BruteRefusesLargeScenes) {
    const scenes::SceneSource s = scenes::load_scene("random:100001");
    auto brute = make_engine("brute");
    EXPECT_THROW(brute->build(s.scene, EngineOptions{}), Error);
}

namespace {

// One timed pass of `engines` on primary rays of a size x size image of `scene`.
BenchResult bench_once(const std::string& scene, int size, const std::vector<std::string>& engines,
                       bool anchor_engines = true) {
    WorkloadConfig config;
    config.scene = scene;
    config.width = config.height = size;
    BenchOptions options;
    options.engines = engines;
    options.repeats = 1;
    options.anchor_engines = anchor_engines;
    return run_bench(make_workload(config), options);
}

}  // namespace

TEST(Bench, ResultsHaveTheJsonContract) {
    const std::vector<std::string> engines = {"kd1", "embree1", "embree16", "brute"};
    const BenchResult r = bench_once("tetra:2", 16, engines);
    const nlohmann::json j = to_json(r);
    for (const char* key : {"scene", "triangles", "mode", "width", "height", "threads", "rays", "engines"})
        EXPECT_TRUE(j.contains(key)) << key;
    for (const std::string& name : engines) {
        const auto& e = j["engines"][name];
        for (const char* key : {"mrays_per_s", "seconds", "build_seconds", "memory_bytes", "hits", "oracle", "stats"})
            EXPECT_TRUE(e.contains(key)) << name << " " << key;
        for (const char* key : {"agree", "ties", "grazing", "mismatch"}) EXPECT_TRUE(e["oracle"].contains(key));
        EXPECT_EQ(e["oracle"]["mismatch"], 0);
        EXPECT_GT(e["mrays_per_s"].get<double>(), 0.0);
    }
    EXPECT_EQ(j["rays"], 256);
    EXPECT_EQ(j["engines"]["kd1"]["hits"], j["engines"]["embree1"]["hits"]);
    EXPECT_TRUE(j["engines"]["kd1"]["stats"].contains("inner_steps_per_ray"));
    EXPECT_EQ(to_table(r).rows(), 5u);  // the four asked for and embree-stream, added for the anchor
}

TEST(Bench, TheAnchorIsTheFastestEmbreeEngineAndEveryEngineIsMeasuredAgainstIt) {
    const BenchResult r = bench_once("tetra:3", 32, {"kd16", "embree16"});
    const nlohmann::json j = to_json(r);
    ASSERT_TRUE(j.contains("anchor"));
    ASSERT_TRUE(j["anchor"].is_object());
    // Every Embree engine runs (the missing ones are added), each timed with both context flags.
    double fastest = 0.0;
    std::string fastest_name;
    for (const std::string& name : anchor_engines()) {
        ASSERT_TRUE(j["engines"].contains(name)) << name;
        const auto& e = j["engines"][name];
        const auto& s = e["stats"];
        for (const char* key : {"coherent_mrays_per_s", "incoherent_mrays_per_s", "context_flag", "robust"})
            ASSERT_TRUE(s.contains(key)) << name << " " << key;
        EXPECT_EQ(s["robust"], true) << name;
        const double coherent = s["coherent_mrays_per_s"], incoherent = s["incoherent_mrays_per_s"];
        EXPECT_DOUBLE_EQ(e["mrays_per_s"].get<double>(), std::max(coherent, incoherent)) << name;
        EXPECT_EQ(s["context_flag"], coherent >= incoherent ? "coherent" : "incoherent") << name;
        EXPECT_EQ(e["oracle"]["mismatch"], 0) << name;
        if (e["mrays_per_s"].get<double>() > fastest) fastest = e["mrays_per_s"], fastest_name = name;
    }
    EXPECT_EQ(j["anchor"]["engine"], fastest_name);
    EXPECT_DOUBLE_EQ(j["anchor"]["mrays_per_s"].get<double>(), fastest);
    EXPECT_EQ(j["anchor"]["context_flag"], j["engines"][fastest_name]["stats"]["context_flag"]);
    for (const auto& [name, e] : j["engines"].items()) {
        ASSERT_TRUE(e.contains("x_anchor")) << name;
        EXPECT_DOUBLE_EQ(e["x_anchor"].get<double>(), e["mrays_per_s"].get<double>() / fastest) << name;
        EXPECT_LE(e["x_anchor"].get<double>(), is_anchor_engine(name) ? 1.0 : 1e9) << name;
    }
    EXPECT_DOUBLE_EQ(j["engines"][fastest_name]["x_anchor"].get<double>(), 1.0);
}

TEST(Bench, WithoutEmbreeEnginesARunHasNoAnchor) {
    const nlohmann::json j = to_json(bench_once("tetra:2", 16, {"kd1"}, false));
    EXPECT_TRUE(j["anchor"].is_null());
    EXPECT_EQ(j["engines"].size(), 1u);
    EXPECT_TRUE(j["engines"]["kd1"]["x_anchor"].is_null());
    // Asked not to add the missing ones, the anchor is the fastest Embree engine listed.
    const nlohmann::json k = to_json(bench_once("tetra:2", 16, {"kd1", "embree1"}, false));
    EXPECT_EQ(k["engines"].size(), 2u);
    EXPECT_EQ(k["anchor"]["engine"], "embree1");
}

TEST(Bench, MlrtaStatsHaveTheJsonContract) {
    // The paper's Table 2 counters of kd16 and mlrta, and the settings that produced them.
    const std::vector<std::string> engines = {"kd16", "mlrta"};
    const nlohmann::json j = to_json(bench_once("tetra:3", 64, engines));
    for (const std::string& name : engines) {
        const auto& s = j["engines"][name]["stats"];
        for (const char* key :
             {"cells_per_packet", "ep_cells_per_packet", "xp_cells_per_packet", "intersections_per_packet", "packets",
              "tiles", "divergent_tiles", "single_rays", "blocked_tiles", "initial_tile", "split_factor", "min_tile",
              "frustum_test", "ep_search", "ep_triangles", "ep_resume", "stuck_stop", "stuck_retry", "kd_nodes"})
            EXPECT_TRUE(s.contains(key)) << name << " " << key;
        EXPECT_NEAR(s["cells_per_packet"].get<double>(),
                    s["ep_cells_per_packet"].get<double>() + s["xp_cells_per_packet"].get<double>(), 1e-9)
            << name;
        EXPECT_EQ(s["packets"], 256) << name;
        EXPECT_EQ(j["engines"][name]["oracle"]["mismatch"], 0) << name;
    }
    EXPECT_EQ(j["engines"]["kd16"]["stats"]["ep_cells_per_packet"], 0.0);
    EXPECT_GT(j["engines"]["mlrta"]["stats"]["ep_cells_per_packet"].get<double>(), 0.0);
    EXPECT_EQ(j["engines"]["mlrta"]["stats"]["ep_resume"], true);
    EXPECT_EQ(j["engines"]["mlrta"]["stats"]["stuck_retry"], true);
}

TEST(Bench, ReleasingWhatTheBenchDoesNotReadChangesNoAnswer) {
    // The bench frees the primary rays, their hits and the pixel indices before building engines.
    for (const Mode mode : {Mode::primary, Mode::ao, Mode::diffuse}) {
        WorkloadConfig config;
        config.scene = "tetra:2";
        config.width = config.height = 24;
        config.mode = mode;
        config.ao_rays = 4;
        BenchOptions options;
        options.engines = {"kd1", "embree1"};
        options.repeats = 1;
        options.anchor_engines = false;
        const BenchResult kept = run_bench(make_workload(config), options);
        Workload w = make_workload(config);
        const std::size_t rays = w.rays.ray_count, slots = w.rays.slots();
        release_untraced(w);
        EXPECT_TRUE(w.primary.packets.empty() && w.primary.pixel.empty() && w.primary_hits.empty());
        EXPECT_TRUE(w.rays.pixel.empty());
        EXPECT_EQ(w.rays.ray_count, rays);
        EXPECT_EQ(w.rays.slots(), slots);
        const BenchResult released = run_bench(w, options);
        ASSERT_EQ(released.engines.size(), kept.engines.size());
        for (std::size_t e = 0; e < kept.engines.size(); ++e) {
            EXPECT_EQ(released.engines[e].hits, kept.engines[e].hits) << to_string(mode);
            EXPECT_EQ(released.engines[e].oracle.mismatch, 0u) << to_string(mode);
        }
    }
}
