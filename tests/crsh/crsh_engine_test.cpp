// The engines crsh and rah against the Embree oracle and brute force on scenes with objects, for
// camera, shadow and AO rays from the scenes' cameras and incoherent rays from everywhere (zero
// mismatch, and the same answers as brute force); their work budget; their statistics, with the
// shape of the paper's Table 1 (crsh < rah < brute force in tests).
#include <gtest/gtest.h>

#include "beamtrace/error.hpp"
#include "experiments/bench_run.hpp"
#include "support/differential.hpp"

using namespace beamtrace;
using namespace beamtrace::workload;
using beamtrace::test::expect_same_answers;

namespace {

std::unique_ptr<Engine> built(const std::string& name, const scenes::SceneSource& source, EngineOptions options = {}) {
    std::unique_ptr<Engine> e = make_engine(name);
    options.object_of_triangle = source.object_of_triangle;
    e->build(source.scene, options);
    return e;
}

}  // namespace

class CrshEngines : public ::testing::TestWithParam<std::string> {};

TEST_P(CrshEngines, AgreeWithEmbreeAndBruteForce) {
    const scenes::SceneSource source = scenes::load_scene(GetParam());
    ASSERT_FALSE(source.object_of_triangle.empty());
    const auto crsh = built("crsh", source), rah = built("rah", source);
    // Brute force where it is quick (the oracle's comparison covers the rest).
    const bool small = source.scene.triangle_count() <= 5000;
    const auto brute = small ? built("brute", source) : nullptr;
    for (const auto& [camera_name, camera] : test::cameras_for(source))
        for (Mode mode : {Mode::primary, Mode::shadow, Mode::ao}) {
            WorkloadConfig config;
            config.camera = camera;
            config.mode = mode;
            config.width = config.height = mode == Mode::ao ? 24 : 40;
            config.ao_rays = 4;
            const Workload w = make_workload(source, config);
            const std::string what = GetParam() + " " + camera_name + " " + to_string(mode);
            for (const Engine* e : {crsh.get(), rah.get()}) {
                test::expect_no_mismatch(check_against_oracle(*e, w, 2), e->name() + " " + what);
                if (brute) expect_same_answers(*e, *brute, w, e->name() + " " + what);
            }
        }
    WorkloadConfig config;
    config.width = config.height = 4;
    Workload w = make_workload(source, config);
    for (Mode mode : {Mode::primary, Mode::shadow}) {
        replace_rays(w, make_random_rays(source.scene.bounds(), 3000, 17, mode));
        for (const Engine* e : {crsh.get(), rah.get()})
            test::expect_no_mismatch(check_against_oracle(*e, w, 2), e->name() + " random " + to_string(mode));
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, CrshEngines, ::testing::Values("tetra:4", "sphereflake:1", "room-lite"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string name;
                             for (char ch : info.param) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
                             return name;
                         });

TEST(CrshEngineBudget, RefusesWorkOverTheBudgetUpFront) {
    const scenes::SceneSource source = scenes::load_scene("tetra:3");
    WorkloadConfig config;
    config.mode = Mode::shadow;
    config.width = config.height = 64;
    const Workload w = make_workload(source, config);
    EngineOptions tight;
    tight.crsh_budget = 10;
    for (const char* name : {"crsh", "rah"}) {
        const auto e = built(name, source, tight);
        try {
            e->prepare(w.rays);
            FAIL() << name << " accepted work over its budget";
        } catch (const Error& error) {
            const std::string message = error.what();
            EXPECT_NE(message.find("budget"), std::string::npos) << message;
            EXPECT_NE(message.find("top nodes"), std::string::npos) << message;
        }
        std::vector<std::uint8_t> occluded;
        EXPECT_THROW(e->occluded(w.rays, occluded, 1), Error);
    }
}

TEST(CrshEngineStats, TotalTestsHaveTheShapeOfTheirTable1) {
    const scenes::SceneSource source = scenes::load_scene("sphereflake:2");
    WorkloadConfig config;
    config.mode = Mode::shadow;
    config.width = config.height = 96;
    const Workload w = make_workload(source, config);
    const nlohmann::json c = built("crsh", source)->stats(w.rays);
    const nlohmann::json r = built("rah", source)->stats(w.rays);
    EXPECT_EQ(c["key"], "end_point");
    EXPECT_EQ(c["objects"], 91);
    EXPECT_EQ(r["objects"], 1);
    for (const nlohmann::json* j : {&c, &r}) {
        const std::uint64_t total = (*j)["total_tests"];
        EXPECT_EQ(total, std::uint64_t((*j)["object_sphere_tests"]) + std::uint64_t((*j)["sphere_cone_tests"]) +
                             std::uint64_t((*j)["triangle_tests"]));
        EXPECT_EQ((*j)["rays"], w.rays.ray_count);
        EXPECT_EQ((*j)["level_stats"].size(), 2u);
    }
    EXPECT_LT(c["total_tests"].get<double>(), r["total_tests"].get<double>());
    EXPECT_LT(r["tests_fraction_of_brute_force"].get<double>(), 1.0);
    EXPECT_GT(c["tests_fraction_of_brute_force"].get<double>(), 0.0);
}
