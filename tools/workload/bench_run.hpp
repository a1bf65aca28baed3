#pragma once
// One benchmark: every engine traces the workload's rays (best of N timed runs), is compared with
// the oracle, and reports its statistics. Results go to a table and to the JSON of `beamtrace bench`.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "oracle/comparison.hpp"
#include "report/table.hpp"
#include "workload/engine.hpp"
#include "workload/workload.hpp"

namespace beamtrace::workload {

struct EngineResult {
    std::string name;
    double mrays_per_s = 0.0;
    double seconds = 0.0;          // best of the timed runs
    double build_seconds = 0.0;
    std::size_t memory_bytes = 0;
    std::uint64_t hits = 0;        // rays with a hit (primary) or occluded (shadow, ao)
    oracle::Tally oracle;
    nlohmann::json stats;
};

struct BenchOptions {
    std::vector<std::string> engines;
    int threads = 1;
    int repeats = 3;
    EngineOptions engine_options;
    bool progress = false;        // progress bars on stderr (only drawn on a terminal)
    std::string progress_label;   // the bars read "build LABEL", "trace LABEL" (default: the engine's name)
};

// An engine's answers to the workload's rays, per slot: hits (primary mode) or occlusion (1 =
// occluded; shadow and ao modes). Inactive slots: no hit, not occluded.
struct EngineAnswers {
    std::vector<Hit> hits;
    std::vector<std::uint8_t> occluded;
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
// Makes and builds the engine (progress bar "build LABEL"); throws for bad options or names.
TimedEngine build_engine(const Workload& workload, const std::string& engine, const BenchOptions& options);
// One timed pass over every ray; the best pass counts.
void time_once(const Workload& workload, TimedEngine& run, int threads);
// Mrays/s of the best pass, build seconds, memory and hits (read after tracing: engines that build
// parts of their structure on first use, vlf, count them). Leaves the oracle counts and statistics.
void summarize_timing(const Workload& workload, TimedEngine& run);

// Builds, runs and checks one engine on the workload.
EngineResult run_engine(const Workload& workload, const std::string& engine, const BenchOptions& options);

struct BenchResult {
    std::string scene;
    std::size_t triangles = 0;
    Mode mode = Mode::primary;
    int width = 0, height = 0, threads = 1;
    std::size_t rays = 0;
    std::vector<EngineResult> engines;
};

BenchResult run_bench(const Workload& workload, const BenchOptions& options);

// {"scene", "triangles", "mode", "width", "height", "threads", "rays", "engines": {NAME: {...}}}
nlohmann::json to_json(const BenchResult& result);
// One row per engine; "x embree1" is the speed ratio to embree1 (or embree16) from the same run.
report::Table to_table(const BenchResult& result);

}  // namespace beamtrace::workload
