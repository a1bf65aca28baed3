// The engines lists and lists-flat against the Embree oracle (zero mismatch) and kd1 (the same
// answers), primary and shadow rays from the scenes' cameras (cameras_for: outside, inside, grazing
// the floor, on the centre planes) and random rays: tetra:0..5 (the paper's Tetra I-VI) here, with
// fewer rays on the bigger ones; tetra:5, random:20000 and the shared bunny and dragon with 64x64 or
// 96x96 images and 20,000 random rays in lists_engine_long_test (label long). Their work budget;
// their statistics with the shape of the paper's Table 1 (flat: tests per ray small, events per ray
// growing with the scene; the hierarchy: far fewer events, the same tests).
#include <gtest/gtest.h>

#include <filesystem>

#include "beamtrace/error.hpp"
#include "experiments/bench_run.hpp"
#include "support/differential.hpp"

using namespace beamtrace;
using namespace beamtrace::workload;
using beamtrace::test::expect_same_answers;

namespace {

struct SceneCase {
    std::string spec;
    bool file = false;
    int size = 48;      // image side of the camera rays
    int random = 5000;  // random rays per mode
};

void PrintTo(const SceneCase& c, std::ostream* os) { *os << c.spec; }

std::unique_ptr<Engine> built(const std::string& name, const Scene& scene) {
    std::unique_ptr<Engine> e = make_engine(name);
    e->build(scene, EngineOptions{});
    return e;
}

void run_case(const SceneCase& c) {
    const std::string path = test::scene_path(c.spec, c.file);
    if (c.file && !std::filesystem::exists(path)) GTEST_SKIP() << "shared scene not found: " << path;
    const scenes::SceneSource source = scenes::load_scene(path);
    const auto kd = built("kd1", source.scene);
    std::vector<std::unique_ptr<Engine>> engines;
    engines.push_back(built("lists", source.scene));
    engines.push_back(built("lists-flat", source.scene));
    for (const auto& [camera_name, camera] : test::cameras_for(source))
        for (Mode mode : {Mode::primary, Mode::shadow}) {
            WorkloadConfig config;
            config.camera = camera;
            config.mode = mode;
            config.width = config.height = c.size;
            const Workload w = make_workload(source, config);
            const std::string what = c.spec + " " + camera_name + " " + to_string(mode);
            for (const auto& e : engines) {
                test::expect_no_mismatch(check_against_oracle(*e, w, 2), e->name() + " " + what);
                expect_same_answers(*e, *kd, w, e->name() + " " + what);
            }
        }
    WorkloadConfig config;
    config.width = config.height = 4;
    Workload w = make_workload(source, config);
    for (Mode mode : {Mode::primary, Mode::shadow}) {
        replace_rays(w, make_random_rays(source.scene.bounds(), c.random, 99, mode));
        for (const auto& e : engines) {
            test::expect_no_mismatch(check_against_oracle(*e, w, 2), e->name() + " random " + to_string(mode));
            expect_same_answers(*e, *kd, w, e->name() + " random " + to_string(mode));
        }
    }
}

std::string case_name(const ::testing::TestParamInfo<SceneCase>& info) {
    std::string name;
    for (char ch : info.param.spec) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    return name;
}

}  // namespace

#ifndef BEAMTRACE_LISTS_LONG
class ListsEngines : public ::testing::TestWithParam<SceneCase> {};
TEST_P(ListsEngines, AgreeWithEmbreeAndKd1) { run_case(GetParam()); }

INSTANTIATE_TEST_SUITE_P(Scenes, ListsEngines,
                         ::testing::Values(SceneCase{"tetra:0"}, SceneCase{"tetra:1"}, SceneCase{"tetra:2"},
                                           SceneCase{"tetra:3"}, SceneCase{"tetra:4", false, 32, 2000},
                                           SceneCase{"tetra:5", false, 16, 500}),
                         case_name);

#else
// The big ones (lists-flat walks every triangle's events for every ray): ctest -L long.
class ListsEnginesLong : public ::testing::TestWithParam<SceneCase> {};
TEST_P(ListsEnginesLong, AgreeWithEmbreeAndKd1) { run_case(GetParam()); }

INSTANTIATE_TEST_SUITE_P(Scenes, ListsEnginesLong,
                         ::testing::Values(SceneCase{"tetra:5", false, 64, 20000},
                                           SceneCase{"random:20000", false, 64, 20000},
                                           SceneCase{"bunny00.off", true, 64, 20000},
                                           SceneCase{"ChineseDragon-10kv.off", true, 96, 20000}),
                         case_name);
#endif

#ifndef BEAMTRACE_LISTS_LONG
TEST(ListsEngineBudget, FlatRefusesBigScenes) {
    const scenes::SceneSource source = scenes::load_scene("random:100001");
    try {
        built("lists-flat", source.scene);
        FAIL() << "lists-flat accepted 100,001 triangles";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("refuses"), std::string::npos) << e.what();
    }
    EXPECT_NO_THROW(built("lists", source.scene));
}

TEST(ListsEngineStats, Table1Shape) {
    double flat_events_before = 0.0;
    for (int level = 2; level <= 4; ++level) {
        const scenes::SceneSource source = scenes::load_scene("tetra:" + std::to_string(level));
        WorkloadConfig config;
        config.width = config.height = 32;
        const Workload w = make_workload(source, config);
        const nlohmann::json flat = built("lists-flat", source.scene)->stats(w.rays);
        const nlohmann::json tree = built("lists", source.scene)->stats(w.rays);
        for (const nlohmann::json* j : {&flat, &tree})
            for (const char* key : {"box_tests_per_ray", "triangle_tests_per_ray", "events_per_ray", "memory_bytes",
                                    "build_seconds", "min_tests_per_ray"})
                EXPECT_TRUE(j->contains(key)) << key;
        const double flat_events = flat["events_per_ray"];
        // Events grow with the scene (4x the triangles per level); tests per ray stay small.
        EXPECT_GT(flat_events, 2.0 * flat_events_before);
        flat_events_before = flat_events;
        EXPECT_LT(double(flat["triangle_tests_per_ray"]), 20.0);
        EXPECT_LT(double(tree["events_per_ray"]), flat_events);
        // Both test exactly the triangles whose boxes the ray enters before the closest hit.
        EXPECT_EQ(double(tree["triangle_tests_per_ray"]), double(flat["triangle_tests_per_ray"]));
        EXPECT_GE(double(flat["triangle_tests_per_ray"]), double(flat["min_tests_per_ray"]));
    }
}
#endif
