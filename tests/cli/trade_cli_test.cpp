// `beamtrace trade` as a user runs it: the CSV of every setting, the Pareto plot, one-line errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/command_line.hpp"

namespace fs = std::filesystem;

namespace {

using beamtrace::test::CommandResult;

CommandResult run(const std::string& args) { return beamtrace::test::run_command(args); }

std::vector<std::string> read_lines(const fs::path& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

std::vector<std::string> fields(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream in(line);
    for (std::string f; std::getline(in, f, ',');) out.push_back(f);
    if (!line.empty() && line.back() == ',') out.push_back("");
    return out;
}

// The index of a column of the header (fails the test if it is missing).
std::size_t column(const std::vector<std::string>& header, const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << "no column " << name;
    return std::size_t(it - header.begin());
}

int count_lines(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

}  // namespace

TEST(TradeCli, WritesTheCsvAndThePlot) {
    const fs::path out = beamtrace::test::temp_dir("trade_cli_test") / "primary";
    const CommandResult r =
        run("trade --scene random:2000 --width 64 --height 64 --repeats 1 --min-seconds 0 --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::vector<std::string> lines = read_lines(out / "trade.csv");
    ASSERT_GT(lines.size(), 20u);
    const std::vector<std::string> header = fields(lines[0]);
    for (const char* name : {"engine", "settings", "mrays_per_s", "x_embree16", "build_seconds", "memory_bytes",
                             "agree", "ties", "grazing", "mismatch", "error_rate", "mean_rel_t_error",
                             "max_rel_t_error", "ao_occlusion_mae", "pareto", "note", "x_anchor"})
        column(header, name);
    int vlf_fast = 0, pareto = 0, anchors = 0;
    double fastest_reference = 0.0;
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const std::vector<std::string> row = fields(lines[i]);
        ASSERT_EQ(row.size(), header.size()) << lines[i];
        const std::string engine = row[0];
        vlf_fast += engine == "vlf-fast";
        pareto += row[column(header, "pareto")] == "1";
        EXPECT_GT(std::stod(row[column(header, "mrays_per_s")]), 0.0) << lines[i];
        EXPECT_EQ(std::stoull(row[column(header, "rays")]), 4096u) << lines[i];  // every ray classified
        // x_anchor: the speed over the fastest Embree row's, which is 1 for that row.
        const double x_anchor = std::stod(row[column(header, "x_anchor")]);
        const double x_embree16 = std::stod(row[column(header, "x_embree16")]);
        EXPECT_GT(x_anchor, 0.0) << lines[i];
        if (row[column(header, "note")] == "reference") {
            EXPECT_LE(x_anchor, 1.0 + 1e-9) << lines[i];
            anchors += std::fabs(x_anchor - 1.0) < 1e-9;
            fastest_reference = std::max(fastest_reference, x_embree16);
        }
        if (engine != "vlf-fast") {
            EXPECT_EQ(row[column(header, "mismatch")], "0") << lines[i];  // the exact engines
        }
    }
    EXPECT_EQ(vlf_fast, 12);  // l x n x d
    EXPECT_GE(pareto, 1);
    EXPECT_EQ(anchors, 1);
    EXPECT_GT(fastest_reference, 0.0);
    for (std::size_t i = 1; i < lines.size(); ++i) {  // x_anchor = x_embree16 / the anchor's x_embree16
        const std::vector<std::string> row = fields(lines[i]);
        EXPECT_NEAR(std::stod(row[column(header, "x_anchor")]),
                    std::stod(row[column(header, "x_embree16")]) / fastest_reference,
                    1e-4 * std::stod(row[column(header, "x_anchor")]))
            << lines[i];
    }
    EXPECT_NE(r.output.find("anchor: "), std::string::npos) << r.output;
    ASSERT_TRUE(fs::exists(out / "trade.png"));
    EXPECT_GT(fs::file_size(out / "trade.png"), 1000u);
    std::ifstream png(out / "trade.png", std::ios::binary);
    char sig[4] = {};
    png.read(sig, 4);
    EXPECT_EQ(std::string(sig + 1, 3), "PNG");
}

TEST(TradeCli, AoRowsCarryTheOcclusionError) {
    const fs::path out = beamtrace::test::temp_dir("trade_cli_test") / "ao";
    const CommandResult r =
        run("trade --scene tetra:3 --mode ao --ao-rays 4 --width 32 --height 32 --repeats 1 --min-seconds 0 "
            "--engines embree1,kd1,vlf-fast --out " +
            out.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::vector<std::string> lines = read_lines(out / "trade.csv");
    // header, the three Embree engines (two added for the anchor), kd1 variants, vlf-fast grid
    ASSERT_EQ(lines.size(), 1u + 3u + 8u + 12u);
    const std::vector<std::string> header = fields(lines[0]);
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const std::vector<std::string> row = fields(lines[i]);
        ASSERT_EQ(row.size(), header.size()) << lines[i];
        EXPECT_FALSE(row[column(header, "ao_occlusion_mae")].empty()) << lines[i];
        EXPECT_TRUE(row[column(header, "mean_rel_t_error")].empty()) << lines[i];  // no hit distances here
    }
    EXPECT_TRUE(fs::exists(out / "trade.png"));
}

TEST(TradeCli, BadInputIsOneLineAndExitTwo) {
    const fs::path dir = beamtrace::test::temp_dir("trade_cli_test");
    for (const std::string& args : {"trade --scene tetra:1 --mode sideways --out " + (dir / "x").string(),
                                    "trade --scene tetra:1 --engines nosuch --out " + (dir / "x").string(),
                                    "trade --scene nosuch:3 --out " + (dir / "x").string()}) {
        const CommandResult r = run(args);
        EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
        EXPECT_EQ(count_lines(r.output), 1) << args << ": " << r.output;
    }
    // An --out that cannot be a folder (a file is in the way) fails before any work.
    std::ofstream(dir / "a-file") << "x";
    const CommandResult r = run("trade --scene tetra:1 --out " + (dir / "a-file" / "sub").string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_NE(r.output.find("--out"), std::string::npos) << r.output;
}

TEST(TradeCli, DiffuseRaysInShuffledOrderCarryHitDistanceErrors) {
    const fs::path out = beamtrace::test::temp_dir("trade_cli_test") / "diffuse";
    const CommandResult r =
        run("trade --scene tetra:3 --mode diffuse --order shuffled --width 32 --height 32 --repeats 1 "
            "--min-seconds 0 --engines embree1,kd1,mlrta --out " +
            out.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("mode diffuse, order shuffled"), std::string::npos) << r.output;
    const std::vector<std::string> lines = read_lines(out / "trade.csv");
    // header, the three Embree engines, kd1 variants, mlrta's two (the rays form no image)
    ASSERT_EQ(lines.size(), 1u + 3u + 8u + 2u);
    const std::vector<std::string> header = fields(lines[0]);
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const std::vector<std::string> row = fields(lines[i]);
        ASSERT_EQ(row.size(), header.size()) << lines[i];
        EXPECT_FALSE(row[column(header, "mean_rel_t_error")].empty()) << lines[i];
        EXPECT_EQ(row[column(header, "mismatch")], "0") << lines[i];
    }
}
