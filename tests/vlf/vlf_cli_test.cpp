// The beamtrace command with the VLF-RT engines: vlf and vlf-fast in bench (their options, the
// JSON stats), --ao-dirs psf for every engine, bad settings rejected in one line, the AO picture.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "support/command_line.hpp"

namespace fs = std::filesystem;

namespace {

using beamtrace::test::CommandResult;

CommandResult run(const std::string& args) { return beamtrace::test::run_command(args); }
fs::path temp_dir() { return beamtrace::test::temp_dir("vlf_cli_test"); }

nlohmann::json read_json(const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
}

}  // namespace

TEST(VlfCli, BenchRunsBothEnginesWithTheirOptionsAndStats) {
    const fs::path json = temp_dir() / "primary.json";
    const CommandResult r =
        run("bench --scene tetra:3 --mode primary --engines embree1,vlf,vlf-fast --width 64 "
            "--height 64 --vlf-dirs 33 --vlf-tiles 64 --vlf-depth 2 --repeats 1 --json " +
            json.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = read_json(json);
    for (const char* name : {"vlf", "vlf-fast"}) {
        const nlohmann::json& e = j["engines"][name];
        EXPECT_GT(e["mrays_per_s"].get<double>(), 0.0) << name;
        const nlohmann::json& s = e["stats"];
        for (const char* field : {"psfs_built", "tile_entries", "memory_bytes", "build_seconds", "mean_tiles_per_ray",
                                  "mean_triangle_tests_per_ray"})
            EXPECT_TRUE(s.contains(field)) << name << " " << field;
        EXPECT_EQ(s["directions"], 33);
        EXPECT_EQ(s["tiles"], 64);
        EXPECT_EQ(s["depth"], 2);
        EXPECT_GT(s["psfs_built"].get<int>(), 0);
        EXPECT_LE(s["psfs_built"].get<int>(), 33);
        EXPECT_GT(e["build_seconds"].get<double>(), 0.0);
    }
    EXPECT_EQ(j["engines"]["vlf"]["oracle"]["mismatch"], 0);
    EXPECT_EQ(j["engines"]["vlf"]["stats"]["mode"], "exact");
    EXPECT_EQ(j["engines"]["vlf-fast"]["stats"]["mode"], "fast");
}

TEST(VlfCli, AoAlongPsfDirectionsForEveryEngine) {
    const fs::path json = temp_dir() / "ao.json";
    const CommandResult r =
        run("bench --scene tetra:3 --mode ao --ao-dirs psf --ao-rays 16 --vlf-dirs 33 --engines "
            "embree1,embree16,kd1,vlf --width 48 --height 48 --repeats 1 --json " +
            json.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = read_json(json);
    const auto hits = j["engines"]["embree1"]["hits"].get<std::uint64_t>();
    for (const char* name : {"embree16", "kd1", "vlf"}) {
        EXPECT_EQ(j["engines"][name]["oracle"]["mismatch"], 0) << name;
        EXPECT_EQ(j["engines"][name]["hits"].get<std::uint64_t>(), hits) << name;
    }
    // Each PSF-aligned AO ray stays in one tile.
    EXPECT_LT(j["engines"]["vlf"]["stats"]["mean_tiles_per_ray"].get<double>(), 1.01);
}

TEST(VlfCli, BadSettingsAreOneLineAndExitTwo) {
    for (const char* args : {"--vlf-dirs 100", "--vlf-tiles 0", "--vlf-depth 40", "--mode ao --ao-dirs sphere"}) {
        const CommandResult r = run(std::string("bench --scene tetra:2 --engines vlf --width 8 --height 8 ") + args);
        EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << ": " << r.output;
    }
    const CommandResult r = run("bench --scene tetra:2 --engines vlf --width 8 --height 8 --vlf-dirs 100");
    EXPECT_NE(r.output.find("513"), std::string::npos) << r.output;
}

TEST(VlfCli, RendersAnAmbientOcclusionPicture) {
    const fs::path png = temp_dir() / "ao.png";
    const CommandResult r =
        run("render --scene tetra:3 --engine vlf --shade ao --ao-dirs psf --vlf-dirs 33 --width 32 "
            "--height 32 --out " +
            png.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(fs::exists(png));
    EXPECT_GT(fs::file_size(png), 100u);
}

TEST(VlfCli, MemoryBudgetTakesSizesAndReportsItsStats) {
    const fs::path json = temp_dir() / "budget.json";
    const CommandResult r =
        run("bench --scene tetra:4 --mode ao --ao-dirs psf --ao-rays 16 --engines vlf --vlf-dirs 33 --vlf-tiles 32 "
            "--width 48 --height 48 --repeats 2 --vlf-memory 2M --json " +
            json.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = read_json(json);
    const nlohmann::json& e = j["engines"]["vlf"];
    EXPECT_EQ(e["oracle"]["mismatch"], 0);
    const nlohmann::json& s = e["stats"];
    EXPECT_EQ(s["memory_budget_bytes"].get<std::size_t>(), std::size_t(2) << 20);
    EXPECT_EQ(s["lazy_tiles"], true);
    EXPECT_GT(s["tiles_built"].get<std::size_t>(), 0u);
    EXPECT_GT(s["memory_peak_bytes"].get<std::size_t>(), 0u);
    EXPECT_LE(s["memory_peak_bytes"].get<std::size_t>(), (std::size_t(2) << 20) + (std::size_t(2) << 17));
    for (const char* field : {"tiles_evicted", "tiles_resident", "rebuild_seconds"})
        EXPECT_TRUE(s.contains(field)) << field;
}

TEST(VlfCli, BadMemoryBudgetsAreOneLineAndExitTwo) {
    for (const char* value : {"2X", "G", "1.5", "abc", "2GG", "1e9"}) {
        const CommandResult r =
            run(std::string("bench --scene tetra:2 --engines vlf --width 8 --height 8 --vlf-memory ") + value);
        EXPECT_EQ(r.exit_code, 2) << value << ": " << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << value << ": " << r.output;
        EXPECT_NE(r.output.find("--vlf-memory"), std::string::npos) << value << ": " << r.output;
    }
    for (const char* args : {"--vlf-memory 1K", "--vlf-memory 1G --vlf-eager", "--vlf-memory 1G --no-vlf-lazy-tiles"}) {
        const CommandResult r = run(std::string("bench --scene tetra:2 --engines vlf --width 8 --height 8 ") + args);
        EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
        EXPECT_NE(r.output.find("budget"), std::string::npos) << args << ": " << r.output;
    }
}
