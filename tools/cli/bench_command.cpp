// beamtrace bench: every engine on the same rays, timed (best of N), checked against Embree.
#include <cstdio>
#include <memory>

#include "beamtrace/error.hpp"
#include "cli/commands.hpp"
#include "experiments/animation_run.hpp"
#include "experiments/bench_run.hpp"
#include "scenes/animations.hpp"

namespace beamtrace::cli {

namespace {

struct BenchArgs {
    SceneOptions scene;
    RayOptions rays;
    std::string engines, json, markdown;
    int repeats = 3;
    std::string mlrta_frustum = "inverse";
    std::string mlrta_ep_search = "top-down";
    MlrtaSettings mlrta;
    VlfOptions vlf;
    StreamSettings stream;
    std::string ao_dirs = "random";
    std::string vlf_order = "auto";
    std::string vlf_memory = "0";
    KdBuildRules kd;
    bool anchor_engines = true;
    bool embree_robust = true;
    CrshSettings crsh;
    RayClsSettings raycls;
    double crsh_budget_millions = double(workload::EngineOptions::kDefaultCrshBudget) / 1e6;
    std::vector<int> lists_grid = {2, 2, 2};
    SortedListRules lists;
    std::string animation;
    int frames = 24, samples_per_frame = 1;
    SpaceTimeSettings space_time;
};

std::string bench_header(const workload::BenchResult& r) {
    char buf[512];
    std::snprintf(buf, sizeof buf, "scene %s (%zu triangles), %s, %dx%d, %d thread%s, %zu rays, best of timed runs\n",
                  r.scene.c_str(), r.triangles,
                  workload::describe_rays(r.mode, r.order, r.lights, r.area_light).c_str(), r.width, r.height,
                  r.threads, r.threads == 1 ? "" : "s", r.rays);
    std::string header = buf;
    if (r.anchor) {
        std::snprintf(buf, sizeof buf,
                      "anchor: %s (%s context flag), %.3f Mrays/s: the fastest Embree engine of this run\n",
                      r.anchor->engine.c_str(), r.anchor->context_flag.c_str(), r.anchor->mrays_per_s);
        header += buf;
    } else {
        header += "no anchor: this run has no Embree engine\n";
    }
    return header;
}

std::string animation_header(const workload::AnimationResult& r) {
    char buf[768];
    std::snprintf(buf, sizeof buf,
                  "animation %s on %s (%zu triangles, %zu moving, %zu keyframes): %s\n%d frames of %dx%d, %d time%s "
                  "per frame, primary + shadow rays, %llu rays, %d thread%s; totals over all frames (build + trace)\n",
                  r.animation.c_str(), r.base_scene.c_str(), r.triangles, r.moving_triangles, r.keyframes,
                  r.description.c_str(), r.frames, r.width, r.height, r.samples_per_frame,
                  r.samples_per_frame == 1 ? "" : "s", static_cast<unsigned long long>(r.rays), r.threads,
                  r.threads == 1 ? "" : "s");
    std::string header = buf;
    header += r.anchor ? "anchor: " + *r.anchor + ", the Embree engine with the smallest total\n"
                       : std::string("no anchor: this run has no Embree engine\n");
    if (r.best_rebuild) header += "best per-frame rebuild: " + *r.best_rebuild + "\n";
    return header;
}

// beamtrace bench --animation: the options that make sense for an animation, the run, the report.
void run_animation_bench(const BenchArgs& args, const workload::EngineOptions& engine_options) {
    if (args.rays.mode != "primary" || args.rays.lights != 0 || args.rays.area_light || args.rays.order != "input")
        throw Error(
            "--animation traces each frame's primary rays and their shadow rays to one point light: --mode, "
            "--lights, --area-light and --order do not apply");
    if (!args.scene.camera.empty()) throw Error("--animation: the camera is the animation's (--camera does not apply)");
    workload::AnimationConfig config;
    config.animation = args.animation;
    if (!args.scene.scene.empty()) config.scene = args.scene.scene;
    config.frames = args.frames;
    config.samples_per_frame = args.samples_per_frame;
    config.width = args.scene.width;
    config.height = args.scene.height;
    if (!args.rays.light.empty()) config.light = scenes::parse_point(args.rays.light, "--light");
    config.validate();
    workload::AnimationBenchOptions options;
    options.engines = split_list(args.engines);
    options.threads = args.scene.threads;
    options.engine_options = engine_options;
    options.progress = true;
    options.anchor_engines = args.anchor_engines;
    for (const std::string& e : options.engines) workload::make_animated_engine(e);  // unknown names first
    const workload::AnimationResult result = workload::run_animation(config, options);
    const std::string header = animation_header(result);
    const report::Table table = workload::to_table(result);
    std::printf("%s\n%s", header.c_str(), table.text().c_str());
    std::fflush(stdout);
    if (!args.json.empty()) write_text(args.json, workload::to_json(result).dump(2) + "\n");
    if (!args.markdown.empty()) write_text(args.markdown, header + "\n" + table.markdown());
}

}  // namespace

std::function<void()> add_bench_command(CLI::App& app) {
    auto args = std::make_shared<BenchArgs>();
    CLI::App* cmd = app.add_subcommand("bench", "time engines on the same rays and compare every hit with Embree");
    add_scene_options(*cmd, args->scene, false);
    add_ray_options(*cmd, args->rays);
    cmd->add_option("--animation", args->animation,
                    "time an animation instead of one image: " + scenes::animation_spec_help() +
                        "; each frame's primary and shadow rays, totals over all frames; --scene is the scene it "
                        "animates (default room); engines: raycls-st, embree-mb, embree-refit, embree-dynamic or any "
                        "engine above (rebuilt for each time)");
    cmd->add_option("--frames", args->frames, "--animation: frames over the animation's time [0, 1]")
        ->capture_default_str()
        ->check(CLI::Range(1, 100000));
    cmd->add_option("--raycls-st-bins", args->space_time.time_bins,
                    "raycls-st: time bins over the animation (0: automatic, from how far the moving triangles travel)")
        ->capture_default_str();
    cmd->add_option("--raycls-st-depth", args->space_time.max_depth,
                    "raycls-st: levels of each time bin's 5D tree of moving triangles (32 children each, 0-8)")
        ->capture_default_str();
    cmd->add_option("--raycls-st-min-candidates", args->space_time.min_candidates,
                    "raycls-st: moving cells with at most this many candidates are not subdivided")
        ->capture_default_str();
    cmd->add_option("--raycls-st-kd-binned-above", args->space_time.static_binned_above,
                    "raycls-st: its static kd-tree binned above this many references when --kd-binned-above is 0 "
                    "(0 = the exact sweep)")
        ->capture_default_str();
    cmd->add_option("--raycls-st-keep-calls", args->space_time.keep_calls,
                    "raycls-st: a time bin no query used in this many calls is freed")
        ->capture_default_str();
    cmd->add_option("--samples-per-frame", args->samples_per_frame,
                    "--animation: distinct ray times per frame (shared jitter offsets; 1: the frame's middle)")
        ->capture_default_str()
        ->check(CLI::Range(1, 64));
    std::string names;
    for (const std::string& n : workload::engine_names()) names += (names.empty() ? "" : ", ") + n;
    cmd->add_option("--engines", args->engines, "comma-separated engines: " + names)->required();
    cmd->add_option("--repeats", args->repeats,
                    "timed runs per engine (the best is reported; an animation is one run of all its frames)")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000));
    cmd->add_option("--kd-traversal-cost", args->kd.traversal_cost, "kd-tree SAH: cost of a traversal step")
        ->capture_default_str();
    cmd->add_option("--kd-intersection-cost", args->kd.intersection_cost, "kd-tree SAH: cost of a triangle test")
        ->capture_default_str();
    cmd->add_option("--kd-empty-cell", args->kd.empty_cell_min_volume_fraction,
                    "kd-tree rule 1: cut off empty cells of at least this fraction of the parent volume (0 = off)")
        ->capture_default_str();
    cmd->add_flag("!--kd-no-flat-cell", args->kd.flat_cell_rule,
                  "kd-tree rule 2 off: no preference for planes covered by coplanar triangles");
    cmd->add_option("--kd-max-depth", args->kd.max_depth, "kd-tree: deepest level (0 = automatic)")
        ->capture_default_str();
    cmd->add_option("--kd-binned-above", args->kd.binned_above,
                    "kd-tree: cells with more triangle references than this choose their split among bin "
                    "boundaries, smaller ones by the exact event sweep (0 = exact everywhere)")
        ->capture_default_str();
    cmd->add_option("--kd-bins", args->kd.bins, "kd-tree: bins per axis of the binned cells (--kd-binned-above)")
        ->capture_default_str();
    cmd->add_option("--kd-tiny-cell", args->kd.tiny_cell_min_area_fraction,
                    "kd-tree rule 3: no cells with less than this fraction of the scene box area (0 = off)")
        ->capture_default_str();
    cmd->add_option("--mlrta-tile", args->mlrta.initial_tile, "mlrta: initial tile size in pixels (ITS)")
        ->capture_default_str();
    cmd->add_option("--mlrta-split", args->mlrta.split_factor, "mlrta: sub-tiles per split (SF), 4 or 16")
        ->capture_default_str();
    cmd->add_option("--mlrta-min-tile", args->mlrta.min_tile, "mlrta: minimum tile size in pixels (MTS)")
        ->capture_default_str();
    cmd->add_option("--mlrta-xp-packets", args->mlrta.experimental.xp_packets,
                    "mlrta: packets per side traced together by interval traversal, 1 (the paper's 4x4 packets), 2 "
                    "or 4; pays with --mlrta-min-tile of at least 4 times as many pixels (the paper: "
                    "--mlrta-xp-packets 1 --mlrta-min-tile 4)")
        ->capture_default_str();
    cmd->add_option("--mlrta-frustum", args->mlrta_frustum, "mlrta: entry-point culling, inverse | direct")
        ->capture_default_str();
    cmd->add_option("--mlrta-ep-search", args->mlrta_ep_search,
                    "mlrta: entry-point search order, top-down | bifurcation-stack (the same entry points with "
                    "--no-mlrta-ep-triangles)")
        ->capture_default_str();
    cmd->add_flag("--mlrta-ep-triangles,!--no-mlrta-ep-triangles", args->mlrta.experimental.ep_triangles,
                  "mlrta: entry-point searches of one-origin beams cull leaves by their triangles and stop at a "
                  "triangle that blocks the whole beam (default on)");
    cmd->add_flag("--mlrta-stuck-retry,!--no-mlrta-stuck-retry", args->mlrta.experimental.retry_stuck,
                  "mlrta: with the stuck rule, a stuck tile is still split once unless it is the part of a stuck tile "
                  "or its parts would be single packets (default on)");
    cmd->add_flag("--mlrta-ep-resume,!--no-mlrta-ep-resume", args->mlrta.experimental.ep_resume,
                  "mlrta: a sub-tile's entry-point search starts at the first potential leaf its parent's search found "
                  "(default on; off: from the parent's entry point, as in the paper)");
    cmd->add_flag("--mlrta-shadow-bvh,!--no-mlrta-shadow-bvh", args->mlrta.experimental.shadow_bvh,
                  "mlrta: shadow (occlusion) packets walk a wide BVH the engine builds for them, a packet at a time "
                  "(default on, beyond the paper; off: tiles of beams through the kd-tree, the paper's method; the "
                  "same answers)");
    cmd->add_flag("--mlrta-stuck-stop,!--no-mlrta-stuck-stop", args->mlrta.experimental.stop_when_stuck,
                  "mlrta: stop splitting a tile whose entry point is its parent's (default on; off: the paper's "
                  "schedule, split down to the minimum tile size)");
    cmd->add_flag("--triangle-culling,!--no-triangle-culling", args->mlrta.experimental.triangle_culling,
                  "kd16/mlrta: cull leaf triangles outside a one-origin packet's frustum before testing them (default "
                  "on; --no-triangle-culling turns it off)");
    cmd->add_option("--vlf-dirs", args->vlf.directions, "vlf: beam directions l (2 m^2 + 1: 33, 129, 513, ...)")
        ->capture_default_str();
    cmd->add_option("--vlf-tiles", args->vlf.tiles, "vlf: tiles per side n of each parallel subfield")
        ->capture_default_str();
    cmd->add_option("--vlf-depth", args->vlf.depth, "vlf: tile-BSP depth d (0 = one leaf per tile)")
        ->capture_default_str();
    cmd->add_flag("--vlf-eager", args->vlf.eager,
                  "vlf: build every parallel subfield before tracing (default: on first use)");
    cmd->add_flag("--vlf-lazy-tiles,!--no-vlf-lazy-tiles", args->vlf.lazy_tiles,
                  "vlf: build each tile the first time a ray reaches it (default on; off: a whole parallel subfield "
                  "on its first use, the same answers)");
    cmd->add_option("--vlf-memory", args->vlf_memory,
                    "vlf: memory budget of the field, e.g. 2G or 512M (0 = unbounded): the least recently used tiles "
                    "are freed and rebuilt when needed (docs/vlf.md)")
        ->capture_default_str();
    cmd->add_option("--vlf-order", args->vlf_order,
                    "vlf: trace rays as given (input), binned by PSF (psf), or binned for occlusion rays only (auto)")
        ->capture_default_str();
    cmd->add_flag("--stream-sort,!--no-stream-sort", args->stream.sort,
                  "stream: hash, sort and group the rays (default on; off: every ray alone in input order, the same "
                  "answers)");
    cmd->add_flag("--stream-loose-groups,!--no-stream-loose-groups", args->stream.group_loose_rays,
                  "stream: rays in no group (diffuse bounces) go 16 sorted neighbours at a time through the masked "
                  "group traversal (default on; off: one by one, the same answers)");
    cmd->add_flag("--stream-wide-bvh,!--no-stream-wide-bvh", args->stream.wide_bvh,
                  "stream: rays in no group (and every ray with --no-stream-sort) go through a wide BVH built for the "
                  "tracer, one by one (default on; off: the kd-tree's single-ray traversal, the same answers)");
    cmd->add_flag("--stream-bvh-pencils,!--no-stream-bvh-pencils", args->stream.bvh_pencils,
                  "stream: with the wide BVH, occlusion pencils (shadow rays to point lights) walk it a packet of 16 "
                  "at a time (default on; off: the kd-tree's interval traversal, the same answers)");
    cmd->add_flag("--stream-buckets,!--no-stream-buckets", args->stream.bucket_order,
                  "stream: with the wide BVH, a stream with no shared point (ambient occlusion, diffuse bounces) is "
                  "ordered by one bucket pass instead of the whole sort and traced ray by ray through the BVH "
                  "(default on; off: the whole sort and groups, the same answers)");
    cmd->add_option("--stream-min-group", args->stream.min_group_rays,
                    "stream: groups of fewer rays go ray by ray (2 .. 16)")
        ->capture_default_str();
    cmd->add_option("--ao-dirs", args->ao_dirs,
                    "ao mode: random (stratified, cosine weighted) | psf (VLF-RT's --vlf-dirs directions)")
        ->capture_default_str();
    cmd->add_option("--crsh-fanout", args->crsh.fanout,
                    "crsh, rah: rays per level-1 node and children per upper node (the paper's subdivision)")
        ->capture_default_str();
    cmd->add_option("--crsh-levels", args->crsh.levels, "crsh, rah: levels of nodes above the rays (the paper's depth)")
        ->capture_default_str();
    cmd->add_option("--crsh-key-bits", args->crsh.key_position_bits,
                    "crsh: bits per axis of the position in a ray's key, above its direction (0-10)")
        ->capture_default_str();
    cmd->add_flag("--crsh-segment-bound", args->crsh.segment_bound,
                  "crsh, rah: also cull by the rays' segment lengths (not in the paper: docs/crsh.md)");
    cmd->add_option("--crsh-budget", args->crsh_budget_millions,
                    "crsh, rah: refuse ray sets whose predicted top-level sphere tests (top nodes x (objects + "
                    "triangles of the largest object) for crsh, top nodes x triangles for rah) exceed this many "
                    "million (docs/crsh.md)")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    add_raycls_options(*cmd, args->raycls);
    cmd->add_option("--lists-grid", args->lists_grid,
                    "lists: resolution of the grid that splits a volume, one number or three (x y z), each 1-16")
        ->expected(1, 3);
    cmd->add_option("--lists-leaf", args->lists.leaf_objects,
                    "lists: volumes of at most this many objects are not split")
        ->capture_default_str();
    cmd->add_option("--lists-special", args->lists.special_cell_fraction,
                    "lists: when every centre falls in one cell, objects at least this fraction of the volume on an "
                    "axis go to its special cell")
        ->capture_default_str();
    cmd->add_flag("--anchor-engines,!--no-anchor-engines", args->anchor_engines,
                  "time every Embree engine (embree1, embree16, embree-stream) even when --engines leaves it out, so "
                  "that the anchor, the fastest of them, is Embree at its best (default on; off: the anchor is the "
                  "fastest Embree engine listed, if any)");
    cmd->add_flag("--embree-robust,!--embree-non-robust", args->embree_robust,
                  "Embree engines: build with RTC_SCENE_FLAG_ROBUST, the watertight guarantee our engines give "
                  "(default on; --embree-non-robust measures Embree's faster mode)");
    cmd->add_option("--json", args->json, "write the results as JSON to this file");
    cmd->add_option("--markdown", args->markdown, "write the table as Markdown to this file");
    return [args, cmd] {
        workload::WorkloadConfig wc = workload_config(args->scene, args->rays);
        wc.ao_directions = workload::AoDirections{workload::parse_ao_directions(args->ao_dirs), args->vlf.directions};
        workload::BenchOptions bo;
        bo.engines = split_list(args->engines);
        bo.threads = args->scene.threads;
        bo.repeats = args->repeats;
        bo.progress = true;
        bo.anchor_engines = args->anchor_engines;
        bo.engine_options.embree_robust = args->embree_robust;
        if (args->mlrta_frustum != "inverse" && args->mlrta_frustum != "direct")
            throw Error("--mlrta-frustum must be inverse or direct, not '" + args->mlrta_frustum + "'");
        args->mlrta.experimental.frustum_test =
            args->mlrta_frustum == "direct" ? FrustumTest::direct : FrustumTest::inverse;
        if (args->mlrta_ep_search != "top-down" && args->mlrta_ep_search != "bifurcation-stack")
            throw Error("--mlrta-ep-search must be top-down or bifurcation-stack, not '" + args->mlrta_ep_search + "'");
        args->mlrta.experimental.ep_search =
            args->mlrta_ep_search == "top-down" ? EpSearch::top_down : EpSearch::bifurcation_stack;
        args->mlrta.validate();
        bo.engine_options.mlrta = args->mlrta;
        KdBuildRules kd = args->kd;
        kd.empty_cell_rule = kd.empty_cell_min_volume_fraction > 0.0f;
        if (!kd.empty_cell_rule) kd.empty_cell_min_volume_fraction = 0.1f;
        kd.tiny_cell_rule = kd.tiny_cell_min_area_fraction > 0.0f;
        kd.validate();
        bo.engine_options.kd_rules = kd;
        args->vlf.memory_budget_bytes = parse_byte_size(args->vlf_memory, "--vlf-memory");
        args->vlf.validate();
        if (args->vlf_order != "input" && args->vlf_order != "psf" && args->vlf_order != "auto")
            throw Error("--vlf-order must be input, psf or auto, not '" + args->vlf_order + "'");
        args->vlf.order = args->vlf_order == "input" ? VlfOrder::input
                          : args->vlf_order == "psf" ? VlfOrder::psf
                                                     : VlfOrder::automatic;
        bo.engine_options.vlf = args->vlf;
        args->stream.validate();
        bo.engine_options.stream = args->stream;
        args->crsh.validate();
        bo.engine_options.crsh = args->crsh;
        bo.engine_options.crsh_budget = static_cast<std::uint64_t>(args->crsh_budget_millions * 1e6);
        args->raycls.validate();
        bo.engine_options.raycls = args->raycls;
        args->space_time.validate();
        bo.engine_options.space_time = args->space_time;
        if (args->lists_grid.size() == 2) throw Error("--lists-grid takes one number or three, not two");
        for (int a = 0; a < 3; ++a)
            args->lists.grid[a] = args->lists_grid[args->lists_grid.size() == 3 ? std::size_t(a) : 0];
        args->lists.validate();
        bo.engine_options.lists = args->lists;
        if (!args->animation.empty()) {
            run_animation_bench(*args, bo.engine_options);
            return;
        }
        for (const char* only : {"--frames", "--samples-per-frame", "--raycls-st-bins", "--raycls-st-depth",
                                 "--raycls-st-min-candidates", "--raycls-st-keep-calls", "--raycls-st-kd-binned-above"})
            if (cmd->count(only) > 0) throw Error(std::string(only) + " applies to --animation only");
        if (args->scene.scene.empty()) throw Error("--scene is required (or --animation)");
        for (const std::string& e : bo.engines) workload::make_engine(e);  // reject unknown names before loading
        workload::Workload w = workload::make_workload(wc);
        workload::release_untraced(w);
        const workload::BenchResult result = workload::run_bench(w, bo);
        const std::string header = bench_header(result);
        const report::Table table = workload::to_table(result);
        std::printf("%s\n%s", header.c_str(), table.text().c_str());
        std::fflush(stdout);
        if (!args->json.empty()) write_text(args->json, workload::to_json(result).dump(2) + "\n");
        if (!args->markdown.empty()) write_text(args->markdown, header + "\n" + table.markdown());
    };
}

}  // namespace beamtrace::cli
