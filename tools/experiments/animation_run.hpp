#pragma once
// One animation benchmark (`beamtrace bench --animation`): every frame's primary rays and shadow
// rays, each ray at one of a few times of its frame, traced frame after frame by every animated
// engine (engines/animated_engine.hpp), build and trace timed, every answer checked against Embree
// built on AnimatedScene::at(t) for that ray's time. Reported as totals over all frames.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engines/animated_engine.hpp"
#include "oracle/comparison.hpp"
#include "report/table.hpp"

namespace beamtrace::workload {

struct AnimationConfig {
    std::string animation = "spin";  // scenes::make_animation's spec
    std::string scene = "room";      // the static scene it animates (scenes::load_scene's spec)
    int frames = 24;
    // Times per frame: frame f (of F) covers [f / F, (f + 1) / F); with S samples its pixels are
    // spread over the S times (f + (j + 0.5) / S) / F, j = 0 .. S - 1, by a fixed hash of the pixel
    // (the shared jitter offsets of a renderer's motion blur). 1: every ray at the frame's middle.
    int samples_per_frame = 1;
    int width = 512, height = 512;
    std::optional<Float3> light;  // default: default_light() of the first frame's camera
    void validate() const;        // throws beamtrace::Error naming the bad setting
};

struct AnimationBenchOptions {
    std::vector<std::string> engines;
    int threads = 1;
    EngineOptions engine_options;
    bool progress = false;
    // Add every Embree engine when missing (embree-mb, embree-refit, embree-dynamic and the static
    // embree1, embree16, embree-stream rebuilt per time), so that the anchor (the smallest Embree
    // total) is Embree at its best on moving geometry.
    bool anchor_engines = true;
};

struct AnimatedEngineResult {
    std::string name;
    bool rebuilds_per_frame = false;
    double start_seconds = 0.0;  // the build every frame shares
    double build_seconds = 0.0;  // per-frame builds, summed (start_seconds included)
    double trace_seconds = 0.0;  // queries, summed over frames
    double total_seconds = 0.0;  // build + trace
    double mrays_per_s = 0.0;    // all rays of all frames over total_seconds
    std::vector<double> frame_seconds;            // build + trace of each frame
    std::vector<std::size_t> frame_memory_bytes;  // held after each frame
    std::size_t memory_peak_bytes = 0;
    std::size_t memory_after_two_frames_bytes = 0;  // the most held after frames 0 and 1
    oracle::Tally primary, shadow;                 // against the oracle, over all frames
    std::vector<std::uint64_t> frame_mismatch;     // primary + shadow mismatches of each frame
    nlohmann::json stats;
    double x_anchor = 0.0;        // the anchor's total over this engine's total (higher: faster)
    double total_vs_best_rebuild = 0.0;  // this engine's total over the best per-frame rebuild's total (lower: faster)
};

struct AnimationResult {
    std::string animation, description, base_scene;
    std::size_t triangles = 0, moving_triangles = 0, keyframes = 0;
    int frames = 0, samples_per_frame = 1, width = 0, height = 0, threads = 1;
    std::uint64_t rays = 0;  // primary + shadow rays of all frames
    double oracle_seconds = 0.0;
    std::vector<AnimatedEngineResult> engines;
    std::optional<std::string> anchor;        // the Embree engine with the smallest total
    std::optional<std::string> best_rebuild;  // the per-frame rebuild engine with the smallest total
};

// Which time sample (0 .. samples - 1) a pixel's rays take.
int time_sample(std::uint32_t pixel, int samples);

AnimationResult run_animation(const AnimationConfig& config, const AnimationBenchOptions& options);

// {"animation", "description", "scene", "triangles", "moving_triangles", "keyframes", "frames",
//  "samples_per_frame", "width", "height", "threads", "rays", "oracle_seconds",
//  "anchor": {"engine", "total_seconds"} | null, "best_rebuild": {"engine", "total_seconds"} | null,
//  "engines": {NAME: {"total_seconds", "build_seconds", "start_seconds", "trace_seconds", "mrays_per_s",
//  "x_anchor", "total_vs_best_rebuild", "rebuilds_per_frame", "memory_peak_bytes",
//  "memory_after_two_frames_bytes", "memory_growth", "frame_seconds", "frame_memory_bytes",
//  "frame_mismatch", "oracle": {primary + shadow}, "oracle_primary", "oracle_shadow", "stats"}}}
nlohmann::json to_json(const AnimationResult& result);
report::Table to_table(const AnimationResult& result);

}  // namespace beamtrace::workload
