// beamtrace trade: every engine under every accuracy-relevant setting on the same rays; writes
// DIR/trade.csv (one row per setting) and DIR/trade.png (Mrays/s against error rate, Pareto front).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <system_error>

#include "beamtrace/error.hpp"
#include "cli/commands.hpp"
#include "experiments/trade_plot.hpp"
#include "experiments/trade_sweep.hpp"

namespace beamtrace::cli {

namespace {

struct TradeArgs {
    SceneOptions scene;
    RayOptions rays;
    std::string engines, out = "trade";
    int repeats = 3;
    double min_seconds = 0.5;
    double vlf_budget_millions = 40.0;
    std::string vlf_memory;
    bool anchor_engines = true;
};

// Creates the output folder and checks that a file can be written in it, before any long work.
void check_output_folder(const std::string& folder) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec || !fs::is_directory(folder))
        throw Error("--out '" + folder + "': cannot create the folder" + (ec ? ": " + ec.message() : std::string()));
    const fs::path probe = fs::path(folder) / ".trade-write-test";
    std::ofstream(probe) << "x";
    const bool ok = fs::is_regular_file(probe, ec) && fs::file_size(probe, ec) == 1;
    fs::remove(probe, ec);
    if (!ok) throw Error("--out '" + folder + "': cannot write files in this folder");
}

std::string trade_header(const workload::TradeResult& r) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "scene %s (%zu triangles), %s, %dx%d, %d thread%s, %zu rays; per setting the best of at least "
                  "%d passes and %g s (each pass followed by one of embree16)\n",
                  r.scene.c_str(), r.triangles,
                  workload::describe_rays(r.mode, r.order, r.lights, r.area_light).c_str(), r.width, r.height,
                  r.threads, r.threads == 1 ? "" : "s", r.rays, r.repeats, r.min_seconds);
    std::string header = buf;
    if (const workload::TradeRow* a = r.anchor()) {
        std::snprintf(buf, sizeof buf,
                      "anchor: %s, the fastest Embree engine (%.2fx embree16); %zu reference%s on the Pareto front\n",
                      a->setting.engine.c_str(), a->x_reference, r.references_on_front(),
                      r.references_on_front() == 1 ? "" : "s");
        header += buf;
    }
    return header;
}

}  // namespace

std::function<void()> add_trade_command(CLI::App& app) {
    auto args = std::make_shared<TradeArgs>();
    args->scene.width = args->scene.height = 256;
    CLI::App* cmd = app.add_subcommand(
        "trade", "speed against accuracy: every engine and setting on the same rays, a CSV and a Pareto plot");
    add_scene_options(*cmd, args->scene);
    add_ray_options(*cmd, args->rays);
    std::string names;
    for (const std::string& n : workload::engine_names())
        if (n != "brute" && n != "crsh" && n != "rah" && n != "lists" && n != "lists-flat") names += (names.empty() ? "" : ", ") + n;
    cmd->add_option("--engines", args->engines, "comma-separated engines to sweep (default: all of " + names + ")");
    cmd->add_option("--repeats", args->repeats, "timed passes per setting at least (the best is reported)")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000));
    cmd->add_option("--min-seconds", args->min_seconds,
                    "keep timing a setting until its passes and embree16's took this long (at most 1000 passes)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 3600.0));
    cmd->add_option("--vlf-budget", args->vlf_budget_millions,
                    "skip VLF-RT settings whose rays need more than this many million triangle-PSFs "
                    "(triangles x parallel subfields to build)")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--vlf-memory", args->vlf_memory,
                    "vlf: also sweep these memory budgets (comma-separated, e.g. 64M,256M,1G) at n = 128, d = 4 "
                    "and every l");
    cmd->add_flag("--anchor-engines,!--no-anchor-engines", args->anchor_engines,
                  "sweep every Embree engine even when --engines leaves it out, so that the anchor is Embree at its "
                  "best (default on)");
    cmd->add_option("--out", args->out, "folder for trade.csv and trade.png")->capture_default_str();
    return [args] {
        const workload::WorkloadConfig wc = workload_config(args->scene, args->rays);
        workload::TradeOptions to;
        to.engines = split_list(args->engines);
        if (!args->engines.empty() && to.engines.empty()) throw Error("--engines: no engine named");
        for (const std::string& e : to.engines) workload::make_engine(e);  // unknown names fail before loading
        to.threads = args->scene.threads;
        to.repeats = args->repeats;
        to.min_seconds = args->min_seconds;
        to.vlf_budget = args->vlf_budget_millions * 1e6;
        for (const std::string& m : split_list(args->vlf_memory))
            to.vlf_memory.push_back(parse_byte_size(m, "--vlf-memory"));
        to.progress = true;
        to.anchor_engines = args->anchor_engines;
        check_output_folder(args->out);
        const workload::Workload w = workload::make_workload(wc);
        const workload::TradeResult result = workload::run_trade(w, to);
        const std::string csv = (std::filesystem::path(args->out) / "trade.csv").string();
        const std::string png = (std::filesystem::path(args->out) / "trade.png").string();
        write_text(csv, workload::to_csv(result));
        std::printf("%s\n%s", trade_header(result).c_str(), workload::to_table(result).text().c_str());
        std::fflush(stdout);
        workload::plot_trade(result, png);
        std::printf("wrote %s and %s\n", csv.c_str(), png.c_str());
    };
}

}  // namespace beamtrace::cli
