// Lazy tiles (VlfOptions::lazy_tiles) and the memory budget (VlfOptions::memory_budget_bytes):
// - a lazily built tile is the whole-PSF build's tile, word for word (every tile of a few PSFs);
// - on every scene of the VLF differential tests, the lazy field, and a lazy field under a budget
//   small enough to evict, answer every ray of the differential workloads exactly as the eagerly
//   built field does, bit for bit, traced on two threads; the budgeted field evicts, rebuilds, and
//   its peak memory stays near its budget;
// - a budget is refused where it cannot work.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <filesystem>

#include "beamtrace/error.hpp"
#include "experiments/bench_run.hpp"
#include "support/differential.hpp"
#include "vlf/build/parallel_subfield.hpp"
#include "vlf/vlf_impl.hpp"

using namespace beamtrace;
using namespace beamtrace::workload;

namespace {

struct SceneCase {
    std::string spec;
    bool file = false;
    int directions = 129;
};

void PrintTo(const SceneCase& c, std::ostream* os) { *os << c.spec << " l=" << c.directions; }

std::string case_name(const ::testing::TestParamInfo<SceneCase>& info) {
    std::string name;
    for (char ch : info.param.spec) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    return name + "_l" + std::to_string(info.param.directions);
}

// The differential tests' scenes and direction counts (vlf_differential_test.cpp).
const auto kScenes = ::testing::Values(SceneCase{"random:20000"}, SceneCase{"random:2000"}, SceneCase{"tetra:5"},
                                       SceneCase{"sphereflake:2", false, 33}, SceneCase{"room", false, 9},
                                       SceneCase{"room:7", false, 3}, SceneCase{"bunny00.off", true},
                                       SceneCase{"ChineseDragon-10kv.off", true});

bool same_hit(const Hit& a, const Hit& b) {
    return a.triangle == b.triangle && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
           std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
           std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

// Every workload of the differential test for this scene: cameras x (primary, shadow, ao random,
// ao along PSF directions), then random primary and shadow rays.
std::vector<Workload> workloads(const scenes::SceneSource& source, int directions) {
    std::vector<Workload> out;
    for (const auto& [camera_name, camera] : test::cameras_for(source)) {
        for (int variant = 0; variant < 4; ++variant) {
            WorkloadConfig config;
            config.camera = camera;
            config.mode = variant == 0 ? Mode::primary : variant == 1 ? Mode::shadow : Mode::ao;
            config.width = config.height = config.mode == Mode::primary ? 96 : 48;
            config.ao_rays = variant == 3 ? 16 : 4;
            if (variant == 3) config.ao_directions = AoDirections{AoDirections::Source::psf, directions};
            out.push_back(make_workload(source, config));
        }
    }
    WorkloadConfig config;
    config.width = config.height = 4;
    for (Mode mode : {Mode::primary, Mode::shadow}) {
        Workload w = make_workload(source, config);
        replace_rays(w, make_random_rays(source.scene.bounds(), 20000, 99, mode));
        out.push_back(std::move(w));
    }
    return out;
}

// Answers of one engine to every workload, per slot (closest hits, or occlusion as 0 / 1).
struct Answers {
    std::vector<std::vector<Hit>> hits;
    std::vector<std::vector<std::uint8_t>> occluded;
};

Answers answer(const Engine& e, const std::vector<Workload>& ws) {
    Answers a;
    for (const Workload& w : ws) {
        a.hits.emplace_back();
        a.occluded.emplace_back();
        if (closest_hit(w.mode))
            e.intersect(w.rays, a.hits.back(), 2);
        else
            e.occluded(w.rays, a.occluded.back(), 2);
    }
    return a;
}

void expect_same(const Answers& want, const Answers& got, const std::vector<Workload>& ws, const std::string& what) {
    for (std::size_t k = 0; k < ws.size(); ++k) {
        ASSERT_EQ(want.hits[k].size(), got.hits[k].size());
        ASSERT_EQ(want.occluded[k].size(), got.occluded[k].size());
        std::size_t differ = 0, rays = 0;
        for (std::size_t s = 0; s < ws[k].rays.slots(); ++s) {
            if (!ws[k].rays.active(s)) continue;
            ++rays;
            if (closest_hit(ws[k].mode) ? !same_hit(want.hits[k][s], got.hits[k][s])
                                        : want.occluded[k][s] != got.occluded[k][s])
                ++differ;
        }
        EXPECT_GT(rays, 0u);
        EXPECT_EQ(differ, 0u) << what << ": workload " << k << " (" << to_string(ws[k].mode) << ") differs on "
                              << differ << " of " << rays << " rays";
    }
}

// The field behind a vlf engine is not reachable from here: the answers are compared through the
// engines, the statistics through a field built with the same options.
std::unique_ptr<Engine> vlf_engine(const Scene& scene, const VlfOptions& o) {
    EngineOptions options;
    options.vlf = o;
    std::unique_ptr<Engine> e = make_engine("vlf");
    e->build(scene, options);
    return e;
}

// What the field holds before any tile, plus one tile table per direction: a safe over-estimate of
// the budget's fixed part.
std::size_t fixed_part(const Scene& scene, const VlfOptions& o) {
    const VisibilityField fresh(scene, o);
    const std::size_t n = std::size_t(o.tiles);
    return fresh.stats().memory_bytes + std::size_t(o.directions) * (n * n * 9 + 4096);
}

}  // namespace

class VlfLazyTiles : public ::testing::TestWithParam<SceneCase> {};

#ifndef BEAMTRACE_VLF_LONG
// Every tile of three PSFs, built lazily one by one, against the whole-PSF build.
TEST_P(VlfLazyTiles, TilesAreTheWholeBuildsWordForWord) {
    const SceneCase& c = GetParam();
    const std::string path = test::scene_path(c.spec, c.file);
    if (c.file && !std::filesystem::exists(path)) GTEST_SKIP() << "shared scene not found: " << path;
    const scenes::SceneSource source = scenes::load_scene(path);
    VlfOptions o;
    o.directions = c.directions;
    const VisibilityField field(source.scene, o);
    const VisibilityField::Impl& f = detail::Access::impl(field);
    const std::uint32_t l = std::uint32_t(c.directions);
    std::size_t nonempty = 0;
    for (std::uint32_t i : {0u, l / 2, l - 1}) {
        const vlf::ParallelSubfield& lazy = f.psf(i);
        ASSERT_TRUE(lazy.lazy());
        const vlf::ParallelSubfield whole(f.frames[i], f.input());
        const std::uint32_t tiles = std::uint32_t(f.grid.n * f.grid.n);
        for (std::uint32_t t = 0; t < tiles; ++t) {
            const vlf::TileRef a = whole.tile(t), b = lazy.tile(t);
            ASSERT_EQ(a.leaves, b.leaves) << "psf " << i << " tile " << t;
            if (a.leaves == 0) continue;
            ++nonempty;
            const std::uint32_t words = whole.view(a).words();
            ASSERT_EQ(words, lazy.view(b).words()) << "psf " << i << " tile " << t;
            ASSERT_EQ(std::memcmp(a.block, b.block, words * sizeof(std::uint32_t)), 0) << "psf " << i << " tile " << t;
        }
    }
    EXPECT_GT(nonempty, 0u);
    const VlfStats s = field.stats();
    EXPECT_EQ(s.tiles_built, 3u * std::size_t(f.grid.n * f.grid.n));
    EXPECT_EQ(s.tiles_evicted, 0u);
    EXPECT_EQ(s.tiles_resident, nonempty);
}
#endif

// The differential workloads' answers of the eagerly built field (whole PSFs, all built first).
static Answers eager_answers(const scenes::SceneSource& source, const std::vector<Workload>& ws, int directions) {
    VlfOptions eager;
    eager.directions = directions;
    eager.lazy_tiles = false;
    eager.eager = true;
    return answer(*vlf_engine(source.scene, eager), ws);
}

// Every workload through a field (two threads, packets as the engines give them).
static void trace_all(const VisibilityField& field, const std::vector<Workload>& ws) {
    for (const Workload& w : ws) {
        if (closest_hit(w.mode)) {
            std::vector<PacketHits16> h(w.rays.packets.size());
            field.intersect(std::span<const Packet16>(w.rays.packets), std::span<PacketHits16>(h),
                            QueryOptions{2, nullptr});
        } else {
            std::vector<std::uint32_t> b(w.rays.packets.size());
            field.occluded(std::span<const Packet16>(w.rays.packets), std::span<std::uint32_t>(b),
                           QueryOptions{2, nullptr});
        }
    }
}

#ifndef BEAMTRACE_VLF_LONG
// Lazy tiles against the eagerly built field.
TEST_P(VlfLazyTiles, AnswersEqualTheEagerFieldBitForBit) {
    const SceneCase& c = GetParam();
    const std::string path = test::scene_path(c.spec, c.file);
    if (c.file && !std::filesystem::exists(path)) GTEST_SKIP() << "shared scene not found: " << path;
    const scenes::SceneSource source = scenes::load_scene(path);
    const std::vector<Workload> ws = workloads(source, c.directions);
    VlfOptions lazy;
    lazy.directions = c.directions;
    expect_same(eager_answers(source, ws, c.directions), answer(*vlf_engine(source.scene, lazy), ws), ws,
                "lazy tiles");
    const VisibilityField field(source.scene, lazy);
    trace_all(field, ws);
    const VlfStats u = field.stats();
    EXPECT_GT(u.tiles_built, 0u);
    EXPECT_EQ(u.tiles_evicted, 0u);
    EXPECT_EQ(u.rebuild_seconds, 0.0);
    EXPECT_EQ(u.memory_peak_bytes, u.memory_bytes);
}
#endif

// Lazy tiles under a budget that holds about a quarter of the tiles the workloads need (so that
// tiles are evicted and rebuilt, many times over) against the eagerly built field.
static void budgeted_case(const SceneCase& c) {
    const std::string path = test::scene_path(c.spec, c.file);
    if (c.file && !std::filesystem::exists(path)) GTEST_SKIP() << "shared scene not found: " << path;
    const scenes::SceneSource source = scenes::load_scene(path);
    const std::vector<Workload> ws = workloads(source, c.directions);
    VlfOptions lazy;
    lazy.directions = c.directions;
    const VisibilityField unbounded(source.scene, lazy);
    trace_all(unbounded, ws);
    const VlfStats u = unbounded.stats();
    const std::size_t fixed = fixed_part(source.scene, lazy);
    const std::size_t n = std::size_t(lazy.tiles);
    const std::size_t tiles =
        u.memory_peak_bytes - VisibilityField(source.scene, lazy).stats().memory_bytes - u.psfs_built * n * n * 9;
    VlfOptions budgeted = lazy;
    budgeted.memory_budget_bytes = fixed + std::max<std::size_t>(std::size_t(1) << 16, tiles / 4);
    expect_same(eager_answers(source, ws, c.directions), answer(*vlf_engine(source.scene, budgeted), ws), ws,
                "lazy tiles, budget " + std::to_string(budgeted.memory_budget_bytes));

    const VisibilityField bounded(source.scene, budgeted);
    for (int pass = 0; pass < 2; ++pass) trace_all(bounded, ws);
    const VlfStats s = bounded.stats();
    std::printf("[ budget ] %s: budget %zu, peak %zu (unbounded peak %zu), stream bins %zu, built %zu, evicted %zu, "
                "rebuild %.3f s\n",
                c.spec.c_str(), budgeted.memory_budget_bytes, s.memory_peak_bytes, u.memory_peak_bytes, s.stream_bytes,
                s.tiles_built, s.tiles_evicted, s.rebuild_seconds);
    EXPECT_GT(s.tiles_evicted, 0u);
    EXPECT_GT(s.tiles_built, s.tiles_resident);
    EXPECT_GT(s.rebuild_seconds, 0.0);
    EXPECT_LE(s.memory_bytes, budgeted.memory_budget_bytes);
    // Past the budget only by the blocks readers built since their last quiescent state (retired,
    // not yet freed): up to +15 % on room:7 at l = 3, whose rays cross dozens of dense tiles between
    // two of them under this tight a budget; within 1 % elsewhere.
    EXPECT_LE(s.memory_peak_bytes, budgeted.memory_budget_bytes + budgeted.memory_budget_bytes / 4);
    // The budget holds the binned streams' buffers too (memory_peak_bytes leaves them to
    // stream_bytes). Budgets this small (tens of MB) cannot spare an eighth for them, and a part of a
    // stream is at least 1,024 packets (about 1.3 MB of bins a thread), so here they come on top of
    // the tiles: 3-16 % over the budget with the tiles at their peak (room:7 at l = 3 the most).
    EXPECT_LE(s.memory_peak_bytes + s.stream_bytes, budgeted.memory_budget_bytes + budgeted.memory_budget_bytes / 4);
}

TEST_P(VlfLazyTiles, UnderABudgetAnswersEqualTheEagerField) {
    const SceneCase& c = GetParam();
#ifndef BEAMTRACE_VLF_LONG
    // The scenes of a million triangles or of many tiles (a minute each under a tight budget)
    // run in the long test.
    if (c.spec.starts_with("room") || c.file) GTEST_SKIP() << "in vlf_lazy_tiles_long_test (ctest -L long)";
#else
    if (!(c.spec.starts_with("room") || c.file)) GTEST_SKIP() << "in vlf_lazy_tiles_test";
#endif
    budgeted_case(c);
}

INSTANTIATE_TEST_SUITE_P(Scenes, VlfLazyTiles, kScenes, case_name);

#ifndef BEAMTRACE_VLF_LONG
TEST(VlfMemoryBudget, RefusedWhereItCannotWork) {
    const scenes::SceneSource source = scenes::load_scene("tetra:3");
    VlfOptions o;
    o.memory_budget_bytes = 1024;
    try {
        const VisibilityField f(source.scene, o);
        ADD_FAILURE() << "a 1 KiB budget was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("fixed part"), std::string::npos) << e.what();
    }
    o.memory_budget_bytes = std::size_t(1) << 30;
    o.lazy_tiles = false;
    EXPECT_THROW(o.validate(), Error);
    o.lazy_tiles = true;
    o.eager = true;
    EXPECT_THROW(o.validate(), Error);
    o.eager = false;
    VisibilityField f(source.scene, o);
    EXPECT_THROW(f.build_all(), Error);
}
#endif
