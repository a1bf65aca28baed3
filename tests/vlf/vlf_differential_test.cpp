// vlf (mode exact) against the Embree oracle: every procedural scene and the shared meshes, from
// outside and inside cameras, a camera grazing along the floor, a camera on the box's centre
// planes, random rays; primary, shadow, ao with random and with PSF directions. Zero `mismatch`.
// vlf-fast is measured on the same rays: its disagreement rate is recorded, and it may only miss
// hits, never report one Embree does not have (up to grazing).
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
    int directions = 129;  // fewer for the million-triangle room, to keep the default run short
    bool fast = true;      // also measure vlf-fast (a second field: left out where memory is short)
};

// Lets gtest (and ctest's list) name the case by its scene instead of dumping its bytes.
void PrintTo(const SceneCase& c, std::ostream* os) { *os << c.spec << " l=" << c.directions; }

// vlf-fast on the workload: the rays where it differs from Embree; each difference must be a
// missed hit (or a farther one), never an extra or nearer hit unless grazing.
struct FastRecord {
    std::uint64_t rays = 0, differ = 0;
};

void check_fast(const Engine& fast, const Workload& w, const std::string& what, FastRecord& record) {
    const Scene& scene = w.source.scene;
    if (closest_hit(w.mode)) {
        std::vector<Hit> hits;
        fast.intersect(w.rays, hits, 2);
        for (std::size_t slot = 0; slot < w.rays.slots(); ++slot) {
            if (!w.rays.active(slot)) continue;
            ++record.rays;
            const Hit& ours = hits[slot];
            const Hit& ref = w.reference_hits[slot];
            if (oracle::classify_hit(scene, w.rays.ray(slot), ours, ref) == oracle::Verdict::agree) continue;
            ++record.differ;
            if (ours.hit() && (!ref.hit() || ours.t < ref.t)) {
                EXPECT_NE(oracle::classify_hit(scene, w.rays.ray(slot), ours, ref), oracle::Verdict::mismatch)
                    << what << ": vlf-fast found a hit nearer than the closest, ray " << slot;
            }
        }
        return;
    }
    std::vector<std::uint8_t> occluded;
    fast.occluded(w.rays, occluded, 2);
    for (std::size_t slot = 0; slot < w.rays.slots(); ++slot) {
        if (!w.rays.active(slot)) continue;
        ++record.rays;
        if (occluded[slot] == w.reference_occluded[slot]) continue;
        ++record.differ;
        if (occluded[slot]) {
            EXPECT_NE(oracle::classify_occlusion(scene, w.rays.ray(slot), true, false), oracle::Verdict::mismatch)
                << what << ": vlf-fast reported an occlusion Embree does not see, ray " << slot;
        }
    }
}

void run_scene(const SceneCase& c) {
    const std::string path = test::scene_path(c.spec, c.file);
    if (c.file && !std::filesystem::exists(path)) GTEST_SKIP() << "shared scene not found: " << path;
    scenes::SceneSource source = scenes::load_scene(path);
    EngineOptions options;
    options.vlf.directions = c.directions;
    std::unique_ptr<Engine> exact = make_engine("vlf"), fast = make_engine("vlf-fast");
    exact->build(source.scene, options);
    if (c.fast) fast->build(source.scene, options);
    FastRecord record;

    for (const auto& [camera_name, camera] : test::cameras_for(source)) {
        for (int variant = 0; variant < 4; ++variant) {
            WorkloadConfig config;
            config.camera = camera;
            config.mode = variant == 0 ? Mode::primary : variant == 1 ? Mode::shadow : Mode::ao;
            config.width = config.height = config.mode == Mode::primary ? 96 : 48;
            config.ao_rays = variant == 3 ? 16 : 4;
            if (variant == 3) config.ao_directions = AoDirections{AoDirections::Source::psf, c.directions};
            const Workload w = make_workload(source, config);
            const std::string what = camera_name + " " + to_string(config.mode) + (variant == 3 ? " psf" : "");
            test::expect_no_mismatch(check_against_oracle(*exact, w, 2), "vlf " + what);
            if (c.fast) check_fast(*fast, w, what, record);
        }
    }
    WorkloadConfig config;
    config.width = config.height = 4;
    Workload w = make_workload(source, config);
    for (Mode mode : {Mode::primary, Mode::shadow}) {
        replace_rays(w, make_random_rays(source.scene.bounds(), 20000, 99, mode));
        test::expect_no_mismatch(check_against_oracle(*exact, w, 2), std::string("vlf random ") + to_string(mode));
        if (c.fast) check_fast(*fast, w, std::string("random ") + to_string(mode), record);
    }
    if (!c.fast) return;
    const double rate = double(record.differ) / double(record.rays);
    ::testing::Test::RecordProperty("vlf_fast_disagreement", std::to_string(rate));
    std::printf("[ vlf-fast ] %s: differs from Embree on %llu of %llu rays (%.2f%%)\n", c.spec.c_str(),
                static_cast<unsigned long long>(record.differ), static_cast<unsigned long long>(record.rays),
                100.0 * rate);
    EXPECT_GT(record.rays, 0u);
}

std::string case_name(const ::testing::TestParamInfo<SceneCase>& info) {
    std::string name;
    for (char ch : info.param.spec) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    return name + "_l" + std::to_string(info.param.directions);
}

}  // namespace

class VlfDifferential : public ::testing::TestWithParam<SceneCase> {};
TEST_P(VlfDifferential, ExactAgreesWithEmbreeAndFastIsMeasured) { run_scene(GetParam()); }

#ifndef BEAMTRACE_VLF_LONG
INSTANTIATE_TEST_SUITE_P(Scenes, VlfDifferential,
                         ::testing::Values(SceneCase{"random:20000"}, SceneCase{"random:2000"}, SceneCase{"tetra:5"},
                                           SceneCase{"sphereflake:2", false, 33}, SceneCase{"room", false, 9},
                                           SceneCase{"room:7", false, 3}, SceneCase{"bunny00.off", true},
                                           SceneCase{"ChineseDragon-10kv.off", true}),
                         case_name);
#else
// The long run (ctest -L long): the default 513 directions everywhere, bigger scenes.
INSTANTIATE_TEST_SUITE_P(Scenes, VlfDifferential,
                         ::testing::Values(SceneCase{"random:100000", false, 513}, SceneCase{"tetra:6", false, 513},
                                           SceneCase{"sphereflake:3", false, 513}, SceneCase{"room", false, 513, false},
                                           SceneCase{"bunny00.off", true, 513},
                                           SceneCase{"ChineseDragon-10kv.off", true, 513}),
                         case_name);
#endif
