// beamtrace: benchmarks and pictures of the library's engines against Embree.
// Exit codes: 0 success, 2 bad input (a bad option, a missing or unreadable file, an empty scene, ...),
// 1 anything unexpected.
#include <cstdio>
#include <exception>

#include "beamtrace/error.hpp"
#include "cli/commands.hpp"
#include "scenes/scene_source.hpp"

namespace beamtrace::cli {

void add_scene_options(CLI::App& command, SceneOptions& o) {
    command.add_option("--scene", o.scene, "scene: a mesh file or a generator\n" + scenes::scene_spec_help())->required();
    command.add_option("--camera", o.camera, "EX,EY,EZ,AX,AY,AZ,FOVY: eye, look-at point, vertical field of view in degrees (default: the scene's own view)");
    command.add_option("--width", o.width, "image width in pixels")->capture_default_str()->check(CLI::Range(1, 65536));
    command.add_option("--height", o.height, "image height in pixels")->capture_default_str()->check(CLI::Range(1, 65536));
    command.add_option("--threads", o.threads, "worker threads")->capture_default_str()->check(CLI::Range(1, 1024));
}

}  // namespace beamtrace::cli

int main(int argc, char** argv) {
    CLI::App app{"beamtrace: SIMD packet and beam ray tracing, measured against Embree"};
    app.require_subcommand(1);
    const auto bench = beamtrace::cli::add_bench_command(app);
    const auto render = beamtrace::cli::add_render_command(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        return 2;
    }
    try {
        if (app.got_subcommand("bench")) bench();
        else render();
        return 0;
    } catch (const beamtrace::Error& e) {
        std::fprintf(stderr, "beamtrace: error: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "beamtrace: internal error: %s\n", e.what());
        return 1;
    }
}
