#include "experiments/animation_run.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "beamtrace/error.hpp"
#include "oracle/comparison_json.hpp"
#include "oracle/embree_oracle.hpp"
#include "report/progress_bar.hpp"
#include "rays/workload.hpp"
#include "scenes/animations.hpp"
#include "report/wall_clock.hpp"

namespace beamtrace::workload {

namespace {

using report::fixed;

using report::seconds_since;

bool is_embree(const std::string& name) { return name.rfind("embree", 0) == 0; }

// One frame's rays and the oracle's answers, with the snapshots the answers were checked on.
struct OracleFrame {
    FrameRays rays;
    FrameAnswers reference;
    std::vector<Scene> snapshots;  // at(times[i])
    std::vector<std::uint8_t> time_index;  // per slot: index into times
};

OracleFrame make_frame(const scenes::AnimationSource& anim, const AnimationConfig& config, int f, Float3 light) {
    OracleFrame out;
    const int s = config.samples_per_frame;
    const float frames = float(config.frames);
    for (int j = 0; j < s; ++j) out.rays.times.push_back((float(f) + (float(j) + 0.5f) / float(s)) / frames);
    const float middle = (float(f) + 0.5f) / frames;
    FrameRays& fr = out.rays;
    fr.primary = make_primary_rays(anim.camera(middle), config.width, config.height);
    fr.slot_time.assign(fr.primary.slots(), 0.0f);
    out.time_index.assign(fr.primary.slots(), 0);
    for (std::size_t slot = 0; slot < fr.primary.slots(); ++slot)
        if (fr.primary.active(slot)) {
            const int j = time_sample(fr.primary.pixel[slot], s);
            fr.slot_time[slot] = fr.times[std::size_t(j)];
            out.time_index[slot] = std::uint8_t(j);
        }
    out.reference.primary.assign(fr.primary.slots(), Hit{});
    out.reference.shadow.assign(fr.primary.slots(), 0);
    for (std::size_t j = 0; j < fr.times.size(); ++j) {
        const float t = fr.times[j];
        out.snapshots.push_back(anim.scene.at(t));
        const Scene& scene = out.snapshots.back();
        const oracle::EmbreeOracle embree(scene);
        const RaySet primary = fr.times.size() == 1 ? fr.primary : rays_at_time(fr.primary, fr.slot_time, t);
        std::vector<Hit> hits(primary.slots(), Hit{});
        for (std::size_t p = 0; p < primary.packets.size(); ++p) {
            if (primary.packets[p].active == 0) continue;
            PacketHits16 h;
            embree.intersect16(primary.packets[p], h);
            for (int i = 0; i < 16; ++i)
                if ((primary.packets[p].active >> i) & 1u) hits[p * 16 + std::size_t(i)] = h.hit(i);
        }
        const RaySet shadow = make_shadow_rays(scene, primary, hits, light);
        if (j == 0) {
            fr.shadow = shadow;
        } else {  // this time's lanes join the frame's shadow rays
            for (std::size_t p = 0; p < shadow.packets.size(); ++p)
                for (std::uint32_t m = shadow.packets[p].active & 0xFFFFu; m; m &= m - 1) {
                    const int i = __builtin_ctz(m);
                    fr.shadow.packets[p].set_ray(i, shadow.packets[p].ray(i));
                    fr.shadow.packets[p].active |= 1u << i;
                }
            fr.shadow.ray_count += shadow.ray_count;
        }
        for (std::size_t p = 0; p < shadow.packets.size(); ++p) {
            if (shadow.packets[p].active == 0) continue;
            const std::uint32_t occluded = embree.occluded16(shadow.packets[p]);
            for (std::uint32_t m = shadow.packets[p].active & 0xFFFFu; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                out.reference.shadow[p * 16 + std::size_t(i)] = (occluded >> i) & 1u;
            }
        }
        for (std::size_t slot = 0; slot < hits.size(); ++slot)
            if (primary.active(slot)) out.reference.primary[slot] = hits[slot];
    }
    return out;
}

// Checks an engine's answers to one frame; returns the frame's mismatches.
std::uint64_t check_frame(const OracleFrame& frame, const FrameAnswers& ours, AnimatedEngineResult& result,
                          std::uint64_t first_slot) {
    const std::uint64_t before = result.primary.mismatch + result.shadow.mismatch;
    const FrameRays& fr = frame.rays;
    for (std::size_t slot = 0; slot < fr.primary.slots(); ++slot) {
        const Scene& scene = frame.snapshots[frame.time_index[slot]];
        if (fr.primary.active(slot))
            result.primary.record_hit(scene, first_slot + slot, fr.primary.ray(slot), ours.primary[slot],
                                      frame.reference.primary[slot]);
        if (fr.shadow.active(slot))
            result.shadow.record_occlusion(scene, first_slot + slot, fr.shadow.ray(slot), ours.shadow[slot] != 0,
                                           frame.reference.shadow[slot] != 0);
    }
    return result.primary.mismatch + result.shadow.mismatch - before;
}

}  // namespace

void AnimationConfig::validate() const {
    if (frames < 1 || frames > 100000) throw Error("--frames must be in 1..100000, not " + std::to_string(frames));
    if (samples_per_frame < 1 || samples_per_frame > 64)
        throw Error("--samples-per-frame must be in 1..64, not " + std::to_string(samples_per_frame));
    if (width < 1 || height < 1) throw Error("animation: the image must be at least 1x1");
}

int time_sample(std::uint32_t pixel, int samples) {
    if (samples <= 1) return 0;
    return int((std::uint64_t(pixel * 0x9E3779B1u) * std::uint64_t(samples)) >> 32);
}

AnimationResult run_animation(const AnimationConfig& config, const AnimationBenchOptions& options) {
    config.validate();
    std::vector<std::string> names = options.engines;
    if (options.anchor_engines)
        for (const char* e : {"embree-mb", "embree-refit", "embree-dynamic", "embree1", "embree16", "embree-stream"})
            if (std::find(names.begin(), names.end(), e) == names.end()) names.push_back(e);
    std::vector<std::unique_ptr<AnimatedEngine>> engines;
    for (const std::string& n : names) engines.push_back(make_animated_engine(n));  // unknown names first

    const scenes::SceneSource base = scenes::load_scene(config.scene);
    const scenes::AnimationSource anim = scenes::make_animation(config.animation, base);
    const Float3 light = config.light ? *config.light : default_light(anim.camera_start, base.scene.bounds());

    AnimationResult r;
    r.animation = anim.name;
    r.description = anim.description;
    r.base_scene = anim.base_scene;
    r.triangles = anim.scene.triangle_count();
    r.moving_triangles = anim.scene.moving_count();
    r.keyframes = anim.scene.keyframe_count();
    r.frames = config.frames;
    r.samples_per_frame = config.samples_per_frame;
    r.width = config.width;
    r.height = config.height;
    r.threads = options.threads;

    r.engines.resize(engines.size());
    for (std::size_t e = 0; e < engines.size(); ++e) {
        AnimatedEngineResult& res = r.engines[e];
        res.name = engines[e]->name();
        res.rebuilds_per_frame = engines[e]->rebuilds_per_frame();
        if (options.progress) std::fprintf(stderr, "build %s\n", res.name.c_str());
        EngineOptions engine_options = options.engine_options;
        engine_options.embree_build_threads = options.threads;  // builds count: Embree's on as many threads
        res.start_seconds = engines[e]->start(anim.scene, engine_options);
        res.build_seconds = res.start_seconds;
    }

    report::ProgressBar bar("frames", options.progress && report::stderr_is_terminal());
    std::uint64_t first_slot = 0;
    for (int f = 0; f < config.frames; ++f) {
        const auto oracle_start = std::chrono::steady_clock::now();
        const OracleFrame frame = make_frame(anim, config, f, light);
        r.oracle_seconds += seconds_since(oracle_start);
        r.rays += frame.rays.primary.ray_count + frame.rays.shadow.ray_count;
        for (std::size_t e = 0; e < engines.size(); ++e) {
            AnimatedEngineResult& res = r.engines[e];
            FrameAnswers answers;
            const FrameSeconds s = engines[e]->trace_frame(frame.rays, answers, options.threads);
            res.build_seconds += s.build;
            res.trace_seconds += s.trace;
            res.frame_seconds.push_back(s.build + s.trace);
            res.frame_memory_bytes.push_back(engines[e]->memory_bytes());
            res.frame_mismatch.push_back(check_frame(frame, answers, res, first_slot));
        }
        first_slot += frame.rays.primary.slots();
        bar.update(double(f + 1) / double(config.frames));
        if (options.progress && !bar.enabled())
            std::fprintf(stderr, "frame %d of %d done\n", f + 1, config.frames);
    }
    bar.finish();

    for (std::size_t e = 0; e < engines.size(); ++e) {
        AnimatedEngineResult& res = r.engines[e];
        res.total_seconds = res.build_seconds + res.trace_seconds;
        res.mrays_per_s = res.total_seconds > 0 ? double(r.rays) / res.total_seconds / 1e6 : 0.0;
        res.memory_peak_bytes = *std::max_element(res.frame_memory_bytes.begin(), res.frame_memory_bytes.end());
        res.memory_after_two_frames_bytes =
            *std::max_element(res.frame_memory_bytes.begin(),
                              res.frame_memory_bytes.begin() + std::min<std::ptrdiff_t>(2, config.frames));
        res.stats = engines[e]->stats();
    }
    const auto fastest = [&](auto&& keep) -> std::optional<std::string> {
        const AnimatedEngineResult* best = nullptr;
        for (const AnimatedEngineResult& res : r.engines)
            if (keep(res) && (best == nullptr || res.total_seconds < best->total_seconds)) best = &res;
        return best ? std::optional<std::string>(best->name) : std::nullopt;
    };
    r.anchor = fastest([](const AnimatedEngineResult& res) { return is_embree(res.name); });
    r.best_rebuild = fastest([](const AnimatedEngineResult& res) { return res.rebuilds_per_frame; });
    const auto total_of = [&](const std::string& name) {
        for (const AnimatedEngineResult& res : r.engines)
            if (res.name == name) return res.total_seconds;
        return 0.0;
    };
    for (AnimatedEngineResult& res : r.engines) {
        if (r.anchor && res.total_seconds > 0) res.x_anchor = total_of(*r.anchor) / res.total_seconds;
        if (r.best_rebuild && total_of(*r.best_rebuild) > 0)
            res.total_vs_best_rebuild = res.total_seconds / total_of(*r.best_rebuild);
    }
    return r;
}

nlohmann::json to_json(const AnimationResult& r) {
    nlohmann::json engines = nlohmann::json::object();
    for (const AnimatedEngineResult& e : r.engines) {
        oracle::Tally both = e.primary;
        both += e.shadow;
        engines[e.name] = {
            {"total_seconds", e.total_seconds},
            {"build_seconds", e.build_seconds},
            {"start_seconds", e.start_seconds},
            {"trace_seconds", e.trace_seconds},
            {"mrays_per_s", e.mrays_per_s},
            {"x_anchor", r.anchor ? nlohmann::json(e.x_anchor) : nlohmann::json(nullptr)},
            {"total_vs_best_rebuild", r.best_rebuild ? nlohmann::json(e.total_vs_best_rebuild) : nlohmann::json(nullptr)},
            {"rebuilds_per_frame", e.rebuilds_per_frame},
            {"memory_peak_bytes", e.memory_peak_bytes},
            {"memory_after_two_frames_bytes", e.memory_after_two_frames_bytes},
            {"memory_growth", e.memory_after_two_frames_bytes
                                  ? double(e.memory_peak_bytes) / double(e.memory_after_two_frames_bytes)
                                  : 0.0},
            {"frame_seconds", e.frame_seconds},
            {"frame_memory_bytes", e.frame_memory_bytes},
            {"frame_mismatch", e.frame_mismatch},
            {"oracle", oracle::to_json(both)},
            {"oracle_primary", oracle::to_json(e.primary)},
            {"oracle_shadow", oracle::to_json(e.shadow)},
            {"stats", e.stats}};
    }
    const auto named = [&](const std::optional<std::string>& name) -> nlohmann::json {
        if (!name) return nullptr;
        for (const AnimatedEngineResult& e : r.engines)
            if (e.name == *name) return {{"engine", e.name}, {"total_seconds", e.total_seconds}};
        return nullptr;
    };
    return {{"animation", r.animation},
            {"description", r.description},
            {"scene", r.base_scene},
            {"triangles", r.triangles},
            {"moving_triangles", r.moving_triangles},
            {"keyframes", r.keyframes},
            {"frames", r.frames},
            {"samples_per_frame", r.samples_per_frame},
            {"width", r.width},
            {"height", r.height},
            {"threads", r.threads},
            {"rays", r.rays},
            {"oracle_seconds", r.oracle_seconds},
            {"anchor", named(r.anchor)},
            {"best_rebuild", named(r.best_rebuild)},
            {"engines", engines}};
}

report::Table to_table(const AnimationResult& r) {
    report::Table t({"engine", "total s", "build s", "trace s", "x best Embree", "x best rebuild", "Mrays/s",
                     "peak MB", "growth", "agree", "ties", "grazing", "mismatch"});
    for (const AnimatedEngineResult& e : r.engines) {
        std::string name = e.name;
        if (r.anchor && e.name == *r.anchor) name += " (anchor)";
        if (r.best_rebuild && e.name == *r.best_rebuild) name += " (best rebuild)";
        oracle::Tally both = e.primary;
        both += e.shadow;
        t.add_row({name, fixed(e.total_seconds, 3), fixed(e.build_seconds, 3), fixed(e.trace_seconds, 3),
                   r.anchor ? fixed(e.x_anchor, 2) : "-", r.best_rebuild ? fixed(e.total_vs_best_rebuild, 2) : "-",
                   fixed(e.mrays_per_s, 3), fixed(double(e.memory_peak_bytes) / 1e6, 1),
                   e.memory_after_two_frames_bytes
                       ? fixed(double(e.memory_peak_bytes) / double(e.memory_after_two_frames_bytes), 2)
                       : "-",
                   std::to_string(both.agree), std::to_string(both.ties), std::to_string(both.grazing),
                   std::to_string(both.mismatch)});
    }
    return t;
}

}  // namespace beamtrace::workload
