#pragma once
// One benchmark: every engine traces the workload's rays (best of N timed runs), is compared with
// the oracle, and reports its statistics. Results go to a table and to the JSON of `beamtrace bench`.
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
    bool progress = false;  // progress bars on stderr (only drawn on a terminal)
};

// Traces the workload's rays once with an engine already built for its scene and sorts every ray
// against the oracle's answer.
oracle::Tally check_against_oracle(const Engine& engine, const Workload& workload, int threads = 1);

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
