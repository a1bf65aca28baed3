#pragma once
// The subcommands of the beamtrace command; each adds itself to the CLI11 app and runs when chosen.
#include <functional>

#include <CLI/CLI.hpp>

namespace beamtrace::cli {

// Registers the subcommand; the returned function runs it after parsing (and may throw).
std::function<void()> add_bench_command(CLI::App& app);
std::function<void()> add_render_command(CLI::App& app);

// Options both commands share: --scene, --camera, --width, --height, --threads.
struct SceneOptions {
    std::string scene;
    std::string camera;
    int width = 1024, height = 1024;
    int threads = 1;
};
void add_scene_options(CLI::App& command, SceneOptions& options);

}  // namespace beamtrace::cli
