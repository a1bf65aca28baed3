// beamtrace render: a picture of what one engine sees.
#include <cstdio>
#include <memory>

#include "beamtrace/error.hpp"
#include "cli/commands.hpp"
#include "report/progress_bar.hpp"
#include "scenes/scene_source.hpp"
#include "experiments/picture.hpp"

namespace beamtrace::cli {

namespace {
struct RenderArgs {
    SceneOptions scene;
    RayOptions rays;
    std::string engine = "kd1", shade = "normal", out;
    std::string ao_dirs = "random";
    int vlf_dirs = DirectionSet::kDefaultCount;
};
}  // namespace

std::function<void()> add_render_command(CLI::App& app) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* cmd = app.add_subcommand("render", "write a PNG picture of what one engine sees");
    add_scene_options(*cmd, args->scene);
    cmd->add_option("--engine", args->engine, "engine that traces the picture")->capture_default_str();
    add_ray_options(*cmd, args->rays);
    CLI::Option* shade =
        cmd->add_option("--shade", args->shade,
                        "normal | depth | ao | shadow | complexity (mlrta: subtree size below each tile's entry "
                        "point); --mode ao and shadow draw that shade, --mode diffuse the bounce hits by normal or "
                        "depth")
            ->capture_default_str();
    cmd->add_option("--ao-dirs", args->ao_dirs, "--shade ao: random | psf (VLF-RT's --vlf-dirs directions)")
        ->capture_default_str();
    cmd->add_option("--vlf-dirs", args->vlf_dirs, "vlf: beam directions l (2 m^2 + 1: 33, 129, 513, ...)")
        ->capture_default_str();
    cmd->add_option("--out", args->out, "PNG file to write")->required();
    return [args, shade] {
        workload::PictureOptions po;
        po.mode = workload::parse_mode(args->rays.mode);
        // --mode ao or shadow without --shade: that shade.
        if (shade->count() == 0 && (po.mode == workload::Mode::ao || po.mode == workload::Mode::shadow))
            args->shade = workload::to_string(po.mode);
        po.shade = workload::parse_shade(args->shade);
        po.width = args->scene.width;
        po.height = args->scene.height;
        po.threads = args->scene.threads;
        po.ao_rays = args->rays.ao_rays;
        po.ao_directions = workload::AoDirections{workload::parse_ao_directions(args->ao_dirs), args->vlf_dirs};
        if (!args->rays.light.empty()) po.light = scenes::parse_point(args->rays.light, "--light");
        po.lights = args->rays.lights;
        po.area_light = args->rays.area_light;
        po.order = workload::parse_order(args->rays.order);
        workload::picture_config(po);  // options that do not go together fail before the scene is loaded
        std::unique_ptr<workload::Engine> engine = workload::make_engine(args->engine);
        const scenes::SceneSource source = scenes::load_scene(args->scene.scene);
        const scenes::Camera camera =
            args->scene.camera.empty() ? source.camera : scenes::parse_camera(args->scene.camera, "--camera");
        {
            report::ProgressBar bar("build " + args->engine);
            workload::EngineOptions eo;
            eo.vlf.directions = args->vlf_dirs;
            eo.vlf.validate();
            eo.object_of_triangle = source.object_of_triangle;
            if (bar.enabled()) eo.build_progress = [&bar](double f) { bar.update(f); };
            engine->build(source.scene, eo);
            bar.finish();
        }
        const report::Image image = workload::render_picture(*engine, source.scene, camera, po);
        report::write_png(image, args->out);
        std::printf("wrote %s (%dx%d, %s, engine %s, scene %s)\n", args->out.c_str(), po.width, po.height,
                    args->shade.c_str(), args->engine.c_str(), source.name.c_str());
    };
}

}  // namespace beamtrace::cli
