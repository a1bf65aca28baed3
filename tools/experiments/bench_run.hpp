#pragma once
// One benchmark: every engine traces the workload's rays (best of N timed runs), is compared with
// the oracle, and reports its statistics. Results go to a table and to the JSON of `beamtrace bench`.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "oracle/comparison.hpp"
#include "report/table.hpp"
#include "engines/engine.hpp"
#include "rays/workload.hpp"

namespace beamtrace::workload {

// The best pass of one way an engine traces (Engine::timing_variants(): Embree's context flags).
struct VariantTiming {
    std::string name;
    double seconds = 1e300;
    double mrays_per_s = 0.0;
};

struct EngineResult {
    std::string name;
    double mrays_per_s = 0.0;
    double seconds = 0.0;  // best of the timed runs (of its fastest variant)
    double build_seconds = 0.0;
    std::size_t memory_bytes = 0;
    std::uint64_t hits = 0;  // rays with a hit (primary) or occluded (shadow, ao)
    oracle::Tally oracle;
    nlohmann::json stats;
    // Engines with timing variants: each one's best pass; the engine's speed is the fastest's.
    std::vector<VariantTiming> variants;
    std::string variant_key;  // the statistic naming the fastest variant ("context_flag")
    double x_anchor = 0.0;    // mrays_per_s over the run's anchor; 0 when the run has none
};

// The Embree engines: the oracle at its documented best, the anchors of every speed ratio.
const std::vector<std::string>& anchor_engines();
bool is_anchor_engine(const std::string& engine);

// The anchor of a run: its fastest Embree engine (each at its faster context flag).
struct Anchor {
    std::string engine;
    double mrays_per_s = 0.0;
    std::string context_flag;
};

struct BenchOptions {
    std::vector<std::string> engines;
    int threads = 1;
    int repeats = 3;
    EngineOptions engine_options;
    bool progress = false;       // progress bars on stderr (only drawn on a terminal)
    std::string progress_label;  // the bars read "build LABEL", "trace LABEL" (default: the engine's name)
    // Add every Embree engine missing from `engines`, so that the run's anchor is Embree at its best
    // (off: the anchor is the fastest Embree engine listed, if any).
    bool anchor_engines = true;
};

// Traces the workload's rays once with an engine already built for its scene and sorts every ray
// against the oracle's answer.
oracle::Tally check_against_oracle(const Engine& engine, const Workload& workload, int threads = 1);

// Sorts each answer against the oracle's (see oracle/comparison.hpp). Occlusion rays that the oracle
// finds occluded and the engine does not are classified with the oracle's closest hit on that ray
// as the triangle hint when oracle_hints is set (one Embree query each), else by the search over
// every triangle of the scene (what `beamtrace bench` does; slow for millions of triangles).
oracle::Tally compare_with_oracle(const Workload& workload, const EngineAnswers& answers, bool oracle_hints = false);

// One engine of a run: built, timed (possibly interleaved with others), then checked.
struct TimedEngine {
    std::unique_ptr<Engine> engine;
    EngineResult result;    // result.seconds: the best timed pass so far
    EngineAnswers answers;  // of the last pass
};
// Makes and builds the engine (progress bar "build LABEL") and prepares it for the workload's rays
// (untimed); throws for bad options or names.
TimedEngine build_engine(const Workload& workload, const std::string& engine, const BenchOptions& options);
// One timed pass over every ray in each of the engine's timing variants; the best pass of each counts.
void time_once(const Workload& workload, TimedEngine& run, int threads);
// Mrays/s of the best pass (of the fastest variant, and of each variant), build seconds, memory
// and hits (read after tracing: engines that build parts of their structure on first use, vlf,
// count them). Leaves the oracle counts and statistics.
void summarize_timing(const Workload& workload, TimedEngine& run);
// The engine's statistics with the speed of each timing variant added
// ("coherent_mrays_per_s", ..., and variant_key: the fastest).
nlohmann::json stats_with_variants(const Engine& engine, const EngineResult& result, const RaySet& rays);

struct BenchResult {
    std::string scene;
    std::size_t triangles = 0;
    Mode mode = Mode::primary;
    Order order = Order::input;
    int lights = 0;           // point lights of shadow rays (point_lights()); 0 in other modes
    bool area_light = false;  // shadow rays to the area light
    int width = 0, height = 0, threads = 1;
    std::size_t rays = 0;
    std::vector<EngineResult> engines;
    std::optional<Anchor> anchor;  // none when the run has no Embree engine
};

// The fastest anchor engine among the results, or none; sets every result's x_anchor.
std::optional<Anchor> find_anchor(std::vector<EngineResult>& results);

BenchResult run_bench(const Workload& workload, const BenchOptions& options);

// {"scene", "triangles", "mode", "width", "height", "threads", "rays",
//  "anchor": {"engine", "mrays_per_s", "context_flag"} (null without one),
//  "order" ("input" | "shuffled"), "lights" (point lights of shadow rays, 0 otherwise), "area_light" (bool),
//  "engines": {NAME: {"mrays_per_s", "x_anchor" (null without an anchor), ...}}}
nlohmann::json to_json(const BenchResult& result);
// One row per engine; "x best Embree" is the speed ratio to the run's anchor.
report::Table to_table(const BenchResult& result);

}  // namespace beamtrace::workload
