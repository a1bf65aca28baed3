#pragma once
// The subcommands of the beamtrace command; each adds itself to the CLI11 app and runs when chosen.
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "beamtrace/ray_classification.hpp"
#include "rays/workload.hpp"

namespace beamtrace::cli {

// Registers the subcommand; the returned function runs it after parsing (and may throw).
std::function<void()> add_bench_command(CLI::App& app);
std::function<void()> add_render_command(CLI::App& app);
std::function<void()> add_trade_command(CLI::App& app);
std::function<void()> add_export_command(CLI::App& app);

// Options both commands share: --scene, --camera, --width, --height, --threads.
struct SceneOptions {
    std::string scene;
    std::string camera;
    int width = 1024, height = 1024;
    int threads = 1;
};
// scene_required false: the command checks --scene itself (bench: not needed with --animation).
void add_scene_options(CLI::App& command, SceneOptions& options, bool scene_required = true);

// "a,b,,c" -> {"a", "b", "c"}.
std::vector<std::string> split_list(const std::string& text);
// A size in bytes: digits (a decimal point allowed) and an optional binary suffix K, M, G or T
// (x 1024^k, case-insensitive, "B" or "iB" may follow): "0", "1048576", "512M", "2G", "1.5GiB".
// Throws beamtrace::Error naming `option` and the text otherwise.
std::size_t parse_byte_size(const std::string& text, const std::string& option);
// Writes a text file, creating its folder; throws beamtrace::Error if it cannot.
void write_text(const std::string& path, const std::string& text);

// Options of the rays bench, trade and render trace: --light, --lights, --area-light, --mode,
// --ao-rays, --order.
struct RayOptions {
    std::string light, mode = "primary";
    int ao_rays = 16;
    int lights = 0;  // 0: not given
    bool area_light = false;
    std::string order = "input";
};
void add_ray_options(CLI::App& command, RayOptions& options);

// raycls's settings: --raycls-depth, --raycls-light-depth, --raycls-min-candidates,
// --raycls-rays-per-cell, --raycls-entries-per-ray, --raycls-memory, --no-raycls-cache,
// --no-light-buffers.
void add_raycls_options(CLI::App& command, RayClsSettings& settings);

// The workload they describe (throws beamtrace::Error for a bad camera, light, mode or order, or
// options that do not go together: WorkloadConfig::validate).
workload::WorkloadConfig workload_config(const SceneOptions& scene, const RayOptions& rays);

}  // namespace beamtrace::cli
