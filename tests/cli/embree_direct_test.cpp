// tools/embree-direct (Embree alone, no beamtrace code) and `beamtrace bench` on the same scene and
// camera find the same hits: the cross-check that the bench's Embree engines trace the rays they
// are meant to, and that the anchor cannot drift from Embree called directly.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenes/camera.hpp"
#include "support/command_line.hpp"
#include "rays/workload.hpp"

namespace fs = std::filesystem;

namespace {

using beamtrace::test::CommandResult;

CommandResult run_embree_direct(const std::string& args) {
    const std::string cmd = std::string(EMBREE_DIRECT) + " " + args + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return {-1, "popen failed"};
    std::string out;
    char buf[4096];
    while (std::fgets(buf, sizeof buf, pipe)) out += buf;
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

// A procedural scene written as an OFF file by `beamtrace export`.
fs::path export_off(const std::string& spec, const fs::path& dir) {
    const fs::path path = dir / "scene.off";
    const CommandResult r = beamtrace::test::run_command("export --scene " + spec + " --out " + path.string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("camera "), std::string::npos) << r.output;
    return path;
}

template <class T>
std::vector<T> read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<T> data(fs::file_size(path) / sizeof(T));
    in.read(reinterpret_cast<char*>(data.data()), std::streamsize(data.size() * sizeof(T)));
    return data;
}

constexpr int kWidth = 70, kHeight = 45;  // partial 4x4 packets at the right and bottom edges
const std::string kCamera = "2.5,1.7,3.1,0.4,0.45,0.35,40";

}  // namespace

TEST(EmbreeDirect, FindsTheSameHitsAsTheBenchOnTheSameRays) {
    const fs::path dir = beamtrace::test::temp_dir("embree_direct_test");
    const fs::path scene = export_off("sphereflake:2", dir);
    const std::string size = " --width " + std::to_string(kWidth) + " --height " + std::to_string(kHeight);
    const CommandResult direct =
        run_embree_direct("--scene " + scene.string() + " --camera " + kCamera + size + " --repeats 1 --json " +
                          (dir / "direct.json").string() + " --dump " + (dir / "direct").string());
    ASSERT_EQ(direct.exit_code, 0) << direct.output;
    const nlohmann::json dj = nlohmann::json::parse(std::ifstream(dir / "direct.json"));
    const std::vector<std::uint32_t> direct_hits = read_file<std::uint32_t>(dir / "direct.primary");
    const std::vector<std::uint8_t> direct_shadow = read_file<std::uint8_t>(dir / "direct.shadow");
    ASSERT_EQ(direct_hits.size(), std::size_t(kWidth * kHeight));
    ASSERT_EQ(direct_shadow.size(), std::size_t(kWidth * kHeight));
    ASSERT_EQ(dj["timings"].size(), 12u);  // {primary, shadow} x {packet16, single, stream} x {coherent, incoherent}
    for (const auto& t : dj["timings"]) EXPECT_GT(t["mrays_per_s"].get<double>(), 0.0) << t.dump();

    // The bench's rays on the same file and camera, pixel by pixel.
    beamtrace::workload::WorkloadConfig config;
    config.scene = scene.string();
    config.camera = beamtrace::scenes::parse_camera(kCamera);
    config.width = kWidth;
    config.height = kHeight;
    config.mode = beamtrace::workload::Mode::shadow;
    const beamtrace::workload::Workload w = beamtrace::workload::make_workload(config);
    std::size_t hits = 0, blocked = 0, compared = 0;
    for (std::size_t slot = 0; slot < w.primary.slots(); ++slot) {
        if (!w.primary.active(slot)) continue;
        const std::uint32_t pixel = w.primary.pixel[slot];
        ++compared;
        ASSERT_EQ(w.primary_hits[slot].triangle, direct_hits[pixel]) << "pixel " << pixel;
        hits += w.primary_hits[slot].hit();
        const bool bench_blocked = w.rays.active(slot) && w.reference_occluded[slot] != 0;
        ASSERT_EQ(bench_blocked, direct_shadow[pixel] != 0) << "pixel " << pixel;
        blocked += bench_blocked;
    }
    EXPECT_EQ(compared, std::size_t(kWidth * kHeight));
    EXPECT_GT(hits, compared / 10);
    EXPECT_GT(blocked, 0u);
    EXPECT_EQ(dj["primary_hits"].get<std::size_t>(), hits);
    EXPECT_EQ(dj["shadow_blocked"].get<std::size_t>(), blocked);

    // And the bench command itself: every Embree engine counts the same hits and blocked rays.
    for (const char* mode : {"primary", "shadow"}) {
        const fs::path json = dir / (std::string(mode) + ".json");
        const CommandResult bench =
            beamtrace::test::run_command("bench --scene " + scene.string() + " --camera " + kCamera + size +
                                         " --mode " + mode + " --engines kd1 --repeats 1 --json " + json.string());
        ASSERT_EQ(bench.exit_code, 0) << bench.output;
        const nlohmann::json bj = nlohmann::json::parse(std::ifstream(json));
        const std::size_t expected = std::string(mode) == "primary" ? hits : blocked;
        for (const char* engine : {"embree1", "embree16", "embree-stream", "kd1"}) {
            EXPECT_EQ(bj["engines"][engine]["hits"].get<std::size_t>(), expected) << mode << " " << engine;
            EXPECT_EQ(bj["engines"][engine]["oracle"]["mismatch"], 0) << mode << " " << engine;
        }
    }
}

TEST(EmbreeDirect, BadInputIsOneLineAndExitTwo) {
    for (const std::string& args : {std::string("--scene /nonexistent.off"), std::string("--width 5"),
                                    std::string("--scene x.off --frobnicate")}) {
        const CommandResult r = run_embree_direct(args);
        EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
        EXPECT_NE(r.output.find("embree-direct: "), std::string::npos) << r.output;
    }
}
