// The beamtrace command as a user runs it: exit codes, one-line errors, the JSON contract, pictures.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "support/command_line.hpp"

namespace fs = std::filesystem;

namespace {

using beamtrace::test::CommandResult;

CommandResult run(const std::string& args) { return beamtrace::test::run_command(args); }
fs::path temp_dir() { return beamtrace::test::temp_dir("cli_test"); }

int lines(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

}  // namespace

TEST(Cli, HelpExitsZero) {
    const CommandResult r = run("bench --help");
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.output.find("--engines"), std::string::npos);
}

TEST(Cli, MissingFileIsOneLineAndExitTwo) {
    const CommandResult r = run("bench --scene /nonexistent/mesh.obj --engines kd1");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(lines(r.output), 1) << r.output;
    EXPECT_NE(r.output.find("/nonexistent/mesh.obj"), std::string::npos) << r.output;
}

TEST(Cli, EmptyAndGarbageFilesAreRejected) {
    const fs::path dir = temp_dir();
    std::ofstream(dir / "empty.obj").close();
    std::ofstream garbage(dir / "garbage.ply", std::ios::binary);
    for (int i = 0; i < 1000; ++i) garbage.put(char((i * 7919) & 0xFF));
    garbage.close();
    for (const char* f : {"empty.obj", "garbage.ply"}) {
        const CommandResult r = run("render --scene " + (dir / f).string() + " --out " + (dir / "x.png").string());
        EXPECT_EQ(r.exit_code, 2) << f << ": " << r.output;
        EXPECT_EQ(lines(r.output), 1) << r.output;
    }
}

TEST(Cli, BadOptionsExitTwo) {
    EXPECT_EQ(run("bench --scene tetra:1 --engines nosuch").exit_code, 2);
    EXPECT_EQ(run("bench --scene tetra:1 --engines kd1 --mode sideways").exit_code, 2);
    EXPECT_EQ(run("bench --scene tetra:1 --engines kd1 --camera 1,2,3").exit_code, 2);
    EXPECT_EQ(run("bench --scene tetra:1 --engines kd1 --width 0").exit_code, 2);
    EXPECT_EQ(run("bench --scene nosuch:3 --engines kd1").exit_code, 2);
    EXPECT_EQ(run("frobnicate").exit_code, 2);
}

TEST(Cli, BenchWritesTheJsonContract) {
    const fs::path json = temp_dir() / "out.json";
    const CommandResult r =
        run("bench --scene tetra:3 --mode shadow --engines kd1,embree1,embree16 --width 64 --height 48 --json " +
            json.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("mismatch"), std::string::npos);
    std::ifstream in(json);
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["mode"], "shadow");
    EXPECT_EQ(j["width"], 64);
    EXPECT_EQ(j["height"], 48);
    EXPECT_EQ(j["threads"], 1);
    for (const char* e : {"kd1", "embree1", "embree16"}) {
        EXPECT_EQ(j["engines"][e]["oracle"]["mismatch"], 0) << e;
        EXPECT_GT(j["engines"][e]["mrays_per_s"].get<double>(), 0.0) << e;
    }
}

TEST(Cli, ComplexityPictureNeedsBeams) {
    const fs::path png = temp_dir() / "complexity.png";
    const CommandResult ok =
        run("render --scene tetra:4 --engine mlrta --shade complexity --width 64 --height 64 --out " + png.string());
    ASSERT_EQ(ok.exit_code, 0) << ok.output;
    EXPECT_TRUE(fs::exists(png));
    const CommandResult bad =
        run("render --scene tetra:4 --engine kd1 --shade complexity --width 64 --height 64 --out " + png.string());
    EXPECT_EQ(bad.exit_code, 2) << bad.output;
    EXPECT_NE(bad.output.find("mlrta"), std::string::npos) << bad.output;
}

TEST(Cli, MlrtaAndKdSettingsAreChecked) {
    EXPECT_EQ(run("bench --scene tetra:1 --engines mlrta --mlrta-split 3").exit_code, 2);
    EXPECT_EQ(run("bench --scene tetra:1 --engines mlrta --mlrta-frustum sideways").exit_code, 2);
    EXPECT_EQ(run("bench --scene tetra:1 --engines mlrta --mlrta-ep-search random").exit_code, 2);
    EXPECT_EQ(run("bench --scene tetra:1 --engines kd1 --kd-intersection-cost -1").exit_code, 2);
    const CommandResult r =
        run("bench --scene tetra:3 --engines kd16,mlrta --width 32 --height 32 --repeats 1 "
            "--mlrta-tile 16 --mlrta-split 4 --mlrta-min-tile 8 --mlrta-frustum direct "
            "--mlrta-ep-search bifurcation-stack --no-triangle-culling --kd-tiny-cell 0");
    EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(Cli, RenderWritesAPng) {
    const fs::path png = temp_dir() / "sub" / "picture.png";
    for (const char* shade : {"normal", "depth", "ao"}) {
        fs::remove(png);
        const CommandResult r =
            run(std::string("render --scene sphereflake:1 --engine kd1 --width 40 --height 30 --ao-rays 4 --shade ") +
                shade + " --out " + png.string());
        ASSERT_EQ(r.exit_code, 0) << r.output;
        std::ifstream in(png, std::ios::binary);
        char sig[8] = {};
        in.read(sig, 8);
        EXPECT_EQ(std::string(sig + 1, 3), "PNG") << shade;
    }
}
