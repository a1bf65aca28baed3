// The beamtrace command as a user runs it: exit codes, one-line errors, the JSON contract, pictures.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

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

TEST(Cli, ListsEnginesAndSettings) {
    EXPECT_EQ(run("bench --scene tetra:1 --engines lists --lists-grid 0").exit_code, 2);
    EXPECT_EQ(run("bench --scene tetra:1 --engines lists --lists-grid 2 2").exit_code, 2);
    EXPECT_EQ(run("bench --scene tetra:1 --engines lists --lists-leaf 0").exit_code, 2);
    EXPECT_EQ(run("bench --scene tetra:1 --engines lists --lists-special 1.5").exit_code, 2);
    const fs::path json = temp_dir() / "lists.json";
    const CommandResult r = run(
        "bench --scene tetra:3 --engines lists,lists-flat --no-anchor-engines --width 32 --height 32 --repeats 1 "
        "--lists-grid 3 2 2 --lists-leaf 2 --json " +
        json.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::ifstream in(json);
    const nlohmann::json j = nlohmann::json::parse(in);
    for (const char* e : {"lists", "lists-flat"}) {
        EXPECT_EQ(j["engines"][e]["oracle"]["mismatch"], 0) << e;
        for (const char* key : {"box_tests_per_ray", "triangle_tests_per_ray", "events_per_ray", "memory_bytes",
                                "build_seconds"})
            EXPECT_TRUE(j["engines"][e]["stats"].contains(key)) << e << " " << key;
    }
    EXPECT_EQ(j["engines"]["lists"]["stats"]["grid"], nlohmann::json::array({3, 2, 2}));
    EXPECT_EQ(j["engines"]["lists"]["stats"]["leaf_objects"], 2);
    EXPECT_EQ(j["engines"]["lists-flat"]["stats"]["volumes"], 1);
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

namespace {

nlohmann::json bench_json(const std::string& args, std::string* output = nullptr) {
    const fs::path json = temp_dir() / "workload.json";
    fs::remove(json);
    const CommandResult r = run("bench --scene tetra:3 --width 32 --height 32 --repeats 1 --engines kd1,mlrta " + args +
                                " --json " + json.string());
    EXPECT_EQ(r.exit_code, 0) << args << ": " << r.output;
    if (output) *output = r.output;
    std::ifstream in(json);
    return nlohmann::json::parse(in);
}

std::string file_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(Cli, BenchJsonNamesTheWorkload) {
    std::string output;
    nlohmann::json j = bench_json("--mode shadow --lights 4 --order shuffled", &output);
    EXPECT_EQ(j["mode"], "shadow");
    EXPECT_EQ(j["order"], "shuffled");
    EXPECT_EQ(j["lights"], 4);
    EXPECT_EQ(j["area_light"], false);
    EXPECT_NE(output.find("mode shadow (4 lights), order shuffled"), std::string::npos) << output;
    for (const char* e : {"kd1", "mlrta", "embree1", "embree16", "embree-stream"})
        EXPECT_EQ(j["engines"][e]["oracle"]["mismatch"], 0) << e;

    j = bench_json("--mode shadow --area-light");
    EXPECT_EQ(j["order"], "input");
    EXPECT_EQ(j["lights"], 0);
    EXPECT_EQ(j["area_light"], true);
    EXPECT_EQ(j["engines"]["mlrta"]["oracle"]["mismatch"], 0);

    j = bench_json("--mode diffuse --order shuffled");
    EXPECT_EQ(j["mode"], "diffuse");
    EXPECT_EQ(j["lights"], 0);
    EXPECT_EQ(j["area_light"], false);
    EXPECT_EQ(j["engines"]["kd1"]["oracle"]["mismatch"], 0);
    EXPECT_EQ(j["engines"]["kd1"]["hits"], j["engines"]["embree1"]["hits"]);

    j = bench_json("--mode shadow");  // the old workload, unchanged: one light, image order
    EXPECT_EQ(j["order"], "input");
    EXPECT_EQ(j["lights"], 1);
    EXPECT_EQ(j["area_light"], false);
    // A markdown file names the workload too.
    const fs::path md = temp_dir() / "workload.md";
    const CommandResult r =
        run("bench --scene tetra:2 --width 16 --height 16 --repeats 1 --engines kd1 "
            "--no-anchor-engines --mode ao --ao-rays 4 --order shuffled --markdown " +
            md.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(file_bytes(md).find("mode ao, order shuffled"), std::string::npos) << file_bytes(md);
}

TEST(Cli, WorkloadOptionsThatDoNotGoTogetherAreOneLineAndExitTwo) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"bench --scene tetra:1 --engines kd1 --mode shadow --lights 2 --light 1,2,3", "--lights and --light"},
        {"bench --scene tetra:1 --engines kd1 --mode shadow --lights 2 --area-light", "--area-light and --lights"},
        {"bench --scene tetra:1 --engines kd1 --mode shadow --area-light --light 1,2,3", "--area-light and --light"},
        {"bench --scene tetra:1 --engines kd1 --area-light", "--area-light applies to shadow rays only"},
        {"bench --scene tetra:1 --engines kd1 --mode ao --lights 3", "--lights applies to shadow rays only"},
        {"bench --scene tetra:1 --engines kd1 --order sideways", "unknown order 'sideways'"},
        {"bench --scene tetra:1 --engines kd1 --mode bounce", "diffuse"},
        {"trade --scene tetra:1 --mode diffuse --lights 2 --out " + (temp_dir() / "t").string(), "--lights applies"},
        {"render --scene tetra:1 --mode ao --shade normal --out " + (temp_dir() / "x.png").string(), "--mode ao"},
        {"render --scene tetra:1 --mode diffuse --shade ao --out " + (temp_dir() / "x.png").string(), "--mode diffuse"},
        {"render --scene tetra:1 --engine mlrta --shade complexity --order shuffled --out " +
             (temp_dir() / "x.png").string(),
         "--order input"},
    };
    for (const auto& [args, expected] : cases) {
        const CommandResult r = run(args);
        EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
        EXPECT_EQ(lines(r.output), 1) << args << ": " << r.output;
        EXPECT_NE(r.output.find(expected), std::string::npos) << args << ": " << r.output;
    }
    EXPECT_EQ(run("bench --scene tetra:1 --engines kd1 --mode shadow --lights 0").exit_code, 2);
}

TEST(Cli, PicturesOfShuffledRaysAreThePicturesOfRaysInImageOrder) {
    const fs::path dir = temp_dir();
    for (const std::string& rays :
         {std::string("--shade normal"), std::string("--mode diffuse"), std::string("--mode diffuse --shade depth"),
          std::string("--mode shadow --lights 3"), std::string("--mode shadow --area-light"),
          std::string("--mode ao --ao-rays 4")}) {
        std::string bytes[2];
        for (int k = 0; k < 2; ++k) {
            const fs::path png = dir / ("order" + std::to_string(k) + ".png");
            fs::remove(png);
            const CommandResult r = run("render --scene sphereflake:1 --engine kd1 --width 40 --height 30 " + rays +
                                        (k ? " --order shuffled" : " --order input") + " --out " + png.string());
            ASSERT_EQ(r.exit_code, 0) << rays << ": " << r.output;
            bytes[k] = file_bytes(png);
        }
        EXPECT_GT(bytes[0].size(), 100u) << rays;
        EXPECT_EQ(bytes[0], bytes[1]) << rays << ": the order changed the picture";
    }
}

TEST(Cli, BenchAnimationWritesTotalsOverAllFrames) {
    const fs::path json = temp_dir() / "animation.json";
    const CommandResult r = run("bench --animation comet --scene room-lite --frames 2 --width 32 --height 24 "
                                "--engines raycls-st,kd1 --json " + json.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("animation comet"), std::string::npos) << r.output;
    std::ifstream in(json);
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["animation"], "comet");
    EXPECT_EQ(j["frames"], 2);
    EXPECT_EQ(j["width"], 32);
    EXPECT_FALSE(j["anchor"].is_null());  // the Embree engines are added
    EXPECT_EQ(j["best_rebuild"]["engine"].get<std::string>().rfind("embree", 0) == 0 ||
                  j["best_rebuild"]["engine"] == "kd1",
              true);
    for (const char* e : {"raycls-st", "kd1", "embree-mb", "embree-refit", "embree-dynamic", "embree16"}) {
        ASSERT_TRUE(j["engines"].contains(e)) << e;
        EXPECT_GT(j["engines"][e]["total_seconds"].get<double>(), 0.0) << e;
        EXPECT_EQ(j["engines"][e]["frame_seconds"].size(), 2u) << e;
    }
    EXPECT_EQ(j["engines"]["raycls-st"]["oracle"]["mismatch"], 0);
    EXPECT_EQ(j["engines"]["kd1"]["oracle"]["mismatch"], 0);
}

TEST(Cli, BenchAnimationOptionsAreChecked) {
    const std::string base = "bench --scene room-lite --width 16 --height 16 --engines raycls-st ";
    for (const std::string bad : {"--animation dance", "--animation party:0", "--animation spin --frames 0",
                                  "--animation spin --mode ao", "--animation spin --camera 0,1,2,3,4,5,60",
                                  "--animation spin --samples-per-frame 65", "--animation spin --raycls-st-depth 9"}) {
        const CommandResult r = run(base + bad);
        EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.output;
        EXPECT_LE(lines(r.output), 2) << bad << "\n" << r.output;
    }
    const CommandResult no_scene = run("bench --engines kd1");
    EXPECT_EQ(no_scene.exit_code, 2);
    EXPECT_NE(no_scene.output.find("--scene"), std::string::npos) << no_scene.output;
    EXPECT_EQ(run("bench --animation spin --scene room-lite --engines nosuch").exit_code, 2);
    const CommandResult stray = run("bench --scene tetra:1 --engines kd1 --frames 3");
    EXPECT_EQ(stray.exit_code, 2);
    EXPECT_NE(stray.output.find("--frames applies to --animation only"), std::string::npos) << stray.output;
    const CommandResult stray_tree = run("bench --scene tetra:1 --engines kd1 --raycls-st-kd-binned-above 0");
    EXPECT_EQ(stray_tree.exit_code, 2);
    EXPECT_NE(stray_tree.output.find("--raycls-st-kd-binned-above applies to --animation only"), std::string::npos)
        << stray_tree.output;
}
