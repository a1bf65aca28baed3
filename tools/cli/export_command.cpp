// beamtrace export: a scene (a file or a generator) written as an OFF file, with the camera the
// other commands use for it, so that another program (tools/embree-direct, another tracer) can
// trace exactly the same triangles and rays.
#include <cstdio>
#include <memory>

#include "cli/commands.hpp"
#include "scenes/camera.hpp"
#include "scenes/off_file.hpp"
#include "scenes/scene_source.hpp"

namespace beamtrace::cli {

namespace {
struct ExportArgs {
    std::string scene, out;
};
}  // namespace

std::function<void()> add_export_command(CLI::App& app) {
    auto args = std::make_shared<ExportArgs>();
    CLI::App* cmd = app.add_subcommand(
        "export",
        "write a scene as an OFF file (same triangles, same ids) and print the camera the other commands use for it");
    cmd->add_option("--scene", args->scene, "scene: a mesh file or a generator\n" + scenes::scene_spec_help())
        ->required();
    cmd->add_option("--out", args->out, "OFF file to write")->required();
    return [args] {
        const scenes::SceneSource source = scenes::load_scene(args->scene);
        write_text(args->out, scenes::format_off(source.scene));
        std::printf("wrote %s (%zu vertices, %zu triangles)\n", args->out.c_str(), source.scene.vertices().size(),
                    source.scene.triangle_count());
        std::printf("camera %s\n", scenes::format_camera(source.camera).c_str());
    };
}

}  // namespace beamtrace::cli
