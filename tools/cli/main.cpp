// beamtrace: benchmarks and pictures of the library's engines against Embree.
// Exit codes: 0 success, 2 bad input (a bad option, a missing or unreadable file, an empty scene, ...),
// 1 anything unexpected.
#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "beamtrace/error.hpp"
#include "cli/commands.hpp"
#include "scenes/scene_source.hpp"

namespace beamtrace::cli {

void add_scene_options(CLI::App& command, SceneOptions& o, bool scene_required) {
    CLI::Option* scene =
        command.add_option("--scene", o.scene, "scene: a mesh file or a generator\n" + scenes::scene_spec_help());
    if (scene_required) scene->required();
    command.add_option("--camera", o.camera,
                       "EX,EY,EZ,AX,AY,AZ,FOVY: eye, look-at point, vertical field of view in degrees (default: the "
                       "scene's own view)");
    command.add_option("--width", o.width, "image width in pixels")->capture_default_str()->check(CLI::Range(1, 65536));
    command.add_option("--height", o.height, "image height in pixels")
        ->capture_default_str()
        ->check(CLI::Range(1, 65536));
    command.add_option("--threads", o.threads, "worker threads")->capture_default_str()->check(CLI::Range(1, 1024));
}

std::vector<std::string> split_list(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ','))
        if (!item.empty()) out.push_back(item);
    return out;
}

std::size_t parse_byte_size(const std::string& text, const std::string& option) {
    // CLI11's size transform (K = 1024, as --raycls-memory), applied by hand for the comma-separated lists.
    std::string value = text;
    std::string problem = text.empty() || !std::isdigit(static_cast<unsigned char>(text[0])) ? "no number" : "";
    std::uint64_t bytes = 0;
    if (problem.empty()) {
        try {
            problem = CLI::AsSizeValue(false)(value);
            std::size_t end = 0;
            if (problem.empty()) bytes = std::stoull(value, &end);
            if (problem.empty() && end != value.size()) problem = "trailing characters";
        } catch (const std::exception& e) {
            problem = e.what();
        }
    }
    if (!problem.empty())
        throw Error(option + ": '" + text +
                    "' is not a size in bytes (a whole number, optionally with K, M, G or T: e.g. 2G, 512M, 0 for none)");
    return static_cast<std::size_t>(bytes);
}

void write_text(const std::string& path, const std::string& text) {
    const std::filesystem::path p(path);
    if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
    std::ofstream out(p);
    out << text;
    if (!out) throw Error("cannot write " + path);
}

void add_ray_options(CLI::App& command, RayOptions& o) {
    command.add_option("--light", o.light,
                       "X,Y,Z point light of shadow rays (default: halfway between camera and scene centre)");
    command
        .add_option("--lights", o.lights,
                    "shadow mode: N point lights spread over the scene's upper box, one ray per hit and light "
                    "(instead of --light)")
        ->check(CLI::Range(1, 4096));
    command.add_flag("--area-light", o.area_light,
                     "shadow mode: one ray per hit to a random point of a square light in the scene's upper box");
    command.add_option("--mode", o.mode, "primary | shadow | ao | diffuse")->capture_default_str();
    command.add_option("--ao-rays", o.ao_rays, "occlusion rays per pixel in ao mode")
        ->capture_default_str()
        ->check(CLI::Range(1, 4096));
    command
        .add_option("--order", o.order,
                    "input (as made: image order) | shuffled (the rays in one fixed random permutation, 16 to a "
                    "packet)")
        ->capture_default_str();
}

void add_raycls_options(CLI::App& command, RayClsSettings& s) {
    command.add_option("--raycls-depth", s.max_depth, "raycls: levels of the 5D tree (32 children each; 0: automatic)")
        ->capture_default_str();
    command
        .add_option("--raycls-light-depth", s.light_buffer_max_depth,
                    "raycls: levels of a light buffer (4 children each; 0: automatic from the triangle count)")
        ->capture_default_str();
    command
        .add_option("--raycls-min-candidates", s.min_candidates,
                    "raycls: cells with at most this many candidates are not subdivided (the thesis's m)")
        ->capture_default_str();
    command
        .add_option("--raycls-rays-per-cell", s.rays_per_new_cell,
                    "raycls: a 5D cell is made once this many rays reach it (the rays before go to the kd-tree)")
        ->capture_default_str();
    command
        .add_option("--raycls-entries-per-ray", s.entries_per_ray,
                    "raycls: at most this many candidate entries made per ray classified (0: no cap); beyond it "
                    "rays whose cell is missing go to the kd-tree")
        ->capture_default_str();
    command
        .add_option("--raycls-memory", s.memory_budget_bytes,
                    "raycls: bytes the lazily made cells may hold, e.g. 512M, 2G (0: unbounded); beyond it rays "
                    "whose cell is missing are traced by the kd-tree and old cells are freed between calls")
        ->transform(CLI::AsSizeValue(false))
        ->capture_default_str();
    command.add_flag("--raycls-cache,!--no-raycls-cache", s.cache,
                     "raycls: try each thread's last cell first (default on)");
    command.add_flag("--light-buffers,!--no-light-buffers", s.light_buffers,
                     "raycls: direction maps around a point every ray of a call ends or starts at (default on)");
    command.add_flag("--raycls-packets,!--no-raycls-packets", s.packet_light_buffers,
                     "raycls: occlusion rays in one light-buffer cell one after another tested 16 at a time (default "
                     "on; off: one by one, the same answers)");
}

workload::WorkloadConfig workload_config(const SceneOptions& scene, const RayOptions& rays) {
    workload::WorkloadConfig wc;
    wc.scene = scene.scene;
    if (!scene.camera.empty()) wc.camera = scenes::parse_camera(scene.camera, "--camera");
    if (!rays.light.empty()) wc.light = scenes::parse_point(rays.light, "--light");
    wc.mode = workload::parse_mode(rays.mode);
    wc.width = scene.width;
    wc.height = scene.height;
    wc.ao_rays = rays.ao_rays;
    wc.lights = rays.lights;
    wc.area_light = rays.area_light;
    wc.order = workload::parse_order(rays.order);
    wc.validate();
    return wc;
}

}  // namespace beamtrace::cli

int main(int argc, char** argv) {
    CLI::App app{"beamtrace: SIMD packet and beam ray tracing, measured against Embree"};
    app.require_subcommand(1);
    const auto bench = beamtrace::cli::add_bench_command(app);
    const auto render = beamtrace::cli::add_render_command(app);
    const auto trade = beamtrace::cli::add_trade_command(app);
    const auto export_scene = beamtrace::cli::add_export_command(app);
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
        if (app.got_subcommand("bench"))
            bench();
        else if (app.got_subcommand("trade"))
            trade();
        else if (app.got_subcommand("export"))
            export_scene();
        else
            render();
        return 0;
    } catch (const beamtrace::Error& e) {
        std::fprintf(stderr, "beamtrace: error: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "beamtrace: internal error: %s\n", e.what());
        return 1;
    }
}
