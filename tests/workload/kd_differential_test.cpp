// kd1, kd16, mlrta, stream and raycls (and brute, where the scene is small; kd1, kd16 and mlrta once
// more on a kd-tree with binned upper levels) against the Embree oracle: every procedural scene and
// the shared meshes, from outside and inside cameras, a camera grazing along the floor, a camera on
// a split plane, random rays; primary, shadow, ao and diffuse rays, shadow rays to several lights and
// to the area light, in input order and (from the scene's own camera) shuffled. Zero `mismatch` everywhere.
#include <gtest/gtest.h>

#include <filesystem>

#include "oracle/comparison.hpp"
#include "support/differential.hpp"
#include "experiments/bench_run.hpp"

using namespace beamtrace;
using namespace beamtrace::workload;

namespace {

struct SceneCase {
    std::string spec;
    bool file = false;
};

// Lets gtest (and ctest's list) name the case by its scene instead of dumping its bytes.
void PrintTo(const SceneCase& c, std::ostream* os) { *os << c.spec; }

}  // namespace

class Differential : public ::testing::TestWithParam<SceneCase> {};

TEST_P(Differential, EnginesAgreeWithEmbree) {
    const SceneCase& c = GetParam();
    const std::string path = test::scene_path(c.spec, c.file);
    if (c.file && !std::filesystem::exists(path)) GTEST_SKIP() << "shared scene not found: " << path;
    scenes::SceneSource source = scenes::load_scene(path);
    std::vector<std::unique_ptr<Engine>> engines;
    for (const char* name : {"kd1", "kd16", "mlrta", "stream", "raycls"}) {
        engines.push_back(make_engine(name));
        engines.back()->build(source.scene, EngineOptions{});
    }
    // MLRTA with every non-default choice: no triangle culling, the direct frustum test, the paper's
    // bifurcation-stack order, splitting down to the minimum size, split factor 4.
    EngineOptions variant;
    variant.mlrta.experimental.triangle_culling = false;
    variant.mlrta.experimental.frustum_test = FrustumTest::direct;
    variant.mlrta.experimental.ep_search = EpSearch::bifurcation_stack;
    variant.mlrta.experimental.stop_when_stuck = false;
    variant.mlrta.split_factor = 4;
    variant.mlrta.initial_tile = 32;
    engines.push_back(make_engine("mlrta"));
    engines.back()->build(source.scene, variant);
    // The kd-tree engines on a tree whose upper levels are binned (cells of more than 256 references).
    EngineOptions binned;
    binned.kd_rules.binned_above = 256;
    for (const char* name : {"kd1", "kd16", "mlrta"}) {
        engines.push_back(make_engine(name));
        engines.back()->build(source.scene, binned);
    }
    if (source.scene.triangle_count() <= 5000) {
        engines.push_back(make_engine("brute"));
        engines.back()->build(source.scene, EngineOptions{});
    }

    struct RayCase {
        Mode mode;
        int lights = 0;
        bool area = false;
    };
    const RayCase ray_cases[] = {{Mode::primary}, {Mode::shadow},    {Mode::ao},
                                 {Mode::diffuse}, {Mode::shadow, 3}, {Mode::shadow, 0, true}};
    bool own_camera = true;  // cameras_for() gives the scene's own camera first
    for (const auto& [camera_name, camera] : test::cameras_for(source)) {
        for (const RayCase& c : ray_cases)
            for (Order order : {Order::input, Order::shuffled}) {
                if (order == Order::shuffled && !own_camera) continue;
                WorkloadConfig config;
                config.camera = camera;
                config.mode = c.mode;
                config.lights = c.lights;
                config.area_light = c.area;
                config.order = order;
                config.width = config.height = c.mode == Mode::primary ? 96 : c.lights > 0 ? 32 : 48;
                config.ao_rays = 4;
                const Workload w = make_workload(source, config);
                const std::string what = describe_rays(c.mode, order, point_lights(w), c.area);
                for (std::size_t i = 0; i < engines.size(); ++i)
                    test::expect_no_mismatch(
                        check_against_oracle(*engines[i], w, 2),
                        engines[i]->name() + "#" + std::to_string(i) + " " + camera_name + " " + what);
            }
        own_camera = false;
    }
    // Incoherent rays from everywhere, closest hit and occlusion.
    WorkloadConfig config;
    config.width = config.height = 4;
    Workload w = make_workload(source, config);
    for (Mode mode : {Mode::primary, Mode::shadow}) {
        replace_rays(w, make_random_rays(source.scene.bounds(), 20000, 99, mode));
        for (const auto& e : engines)
            test::expect_no_mismatch(check_against_oracle(*e, w, 2), e->name() + " random " + to_string(mode));
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, Differential,
                         ::testing::Values(SceneCase{"random:20000"}, SceneCase{"random:2000"}, SceneCase{"tetra:5"},
                                           SceneCase{"sphereflake:2"}, SceneCase{"room"}, SceneCase{"room:7"},
                                           SceneCase{"bunny00.off", true}, SceneCase{"ChineseDragon-10kv.off", true}),
                         [](const ::testing::TestParamInfo<SceneCase>& info) {
                             std::string name;
                             for (char ch : info.param.spec)
                                 name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
                             return name;
                         });
