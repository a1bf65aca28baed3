#pragma once
// The trade between speed and accuracy, measured: every engine under every setting that matters
// (VLF-RT's directions, tiles, BSP depth, exact or fast; the kd-tree's build rules and constants;
// MLRTA's beam settings) traces the same rays, and each setting gets one row: speed, build time,
// memory, the oracle's agree/ties/grazing/mismatch counts, the relative error of hit distances
// (primary rays) and the error of each pixel's occlusion fraction (ao rays).
#include <cstddef>
#include <string>
#include <vector>

#include "report/table.hpp"
#include "experiments/bench_run.hpp"
#include "experiments/error_metrics.hpp"
#include "rays/workload.hpp"

namespace beamtrace::workload {

// One engine under one setting.
struct TradeSetting {
    std::string engine;    // an engine name (engine_names())
    std::string settings;  // the settings of the structure, "l=33 n=64 d=4" (no commas)
    std::string label;     // short name for plots: "vlf-fast 33/64/4", "kd1 no rule 2"
    EngineOptions options;
    std::string skipped;  // why the setting is not measured; empty when it is
};

struct TradeOptions {
    std::vector<std::string> engines;  // engines to sweep; empty: every engine but brute
    int threads = 1;
    int repeats = 3;  // timed passes per setting at least (the best counts)
    // ... and more until the setting's passes and embree16's took this long (at most 1000 passes):
    // small workloads take milliseconds a pass, too few for a best time on a busy machine.
    double min_seconds = 0.5;
    // A VLF-RT setting is skipped when the scene's triangles times the parallel subfields its rays
    // need (counted from the rays' directions) exceed this: about 0.35 s of building per million.
    double vlf_budget = 40e6;
    // Memory budgets (VlfOptions::memory_budget_bytes) swept for vlf at n = 128, d = 4 and every l,
    // besides the unbounded settings; budgets below a field's fixed part are skipped (with the reason).
    std::vector<std::size_t> vlf_memory;
    bool progress = false;  // progress bars on stderr (only drawn on a terminal)
    // Sweep every Embree engine (embree1, embree16, embree-stream) even when `engines` leaves it out,
    // so that the anchor, the fastest of them, is Embree at its best.
    bool anchor_engines = true;
};

// The settings swept for this workload, in the order they are run: embree1, embree16, embree-stream, then kd1
// (rules and constants), kd16, mlrta (beam settings when the rays form an image), vlf and
// vlf-fast (l in {33, 129, 513} x n in {64, 128} x d in {0, 4}; then vlf at n = 128, d = 4 under each
// of options.vlf_memory), keeping the given engines only.
// Throws beamtrace::Error for unknown engine names.
std::vector<TradeSetting> trade_settings(const Workload& workload, const TradeOptions& options);

// The engines the settings are measured against (the Embree engines): their error is zero by construction.
bool is_reference_engine(const std::string& engine);

struct TradeRow {
    TradeSetting setting;
    EngineResult result;  // no engine statistics; oracle counts with the oracle's hints
    // Speed over embree16's, each timed pass of the setting followed by one of embree16 (the best
    // of each), so that a change of machine load while the sweep runs moves both alike.
    double x_reference = 0.0;
    // Speed over the anchor's (the fastest reference row): x_reference / the anchor's x_reference.
    double x_anchor = 0.0;
    RelativeTError t_error;      // primary mode
    double occlusion_mae = 0.0;  // ao mode
    bool pareto = false;         // on the Pareto front of every measured row, the references included

    bool measured() const { return setting.skipped.empty(); }
    // mismatch / rays: the x axis of the plot (grazing and ties are not errors here).
    double error_rate() const;
};

struct TradeResult {
    std::string scene;
    std::size_t triangles = 0;
    Mode mode = Mode::primary;
    Order order = Order::input;
    int lights = 0;           // point lights of shadow rays (point_lights()); 0 in other modes
    bool area_light = false;  // shadow rays to the area light
    int width = 0, height = 0, threads = 1, repeats = 0;
    double min_seconds = 0.0;
    std::size_t rays = 0;
    double reference_mrays_per_s = 0.0;  // embree16's best pass over the whole sweep
    std::vector<TradeRow> rows;
    // The anchor: the measured reference row with the highest x_reference (none if no reference row
    // was measured; x_anchor is then 0 everywhere).
    const TradeRow* anchor() const;
    std::size_t references_on_front() const;

    // The speed the plot shows: x_reference times reference_mrays_per_s (Mrays/s at the load of
    // embree16's best pass).
    double steady_mrays_per_s(const TradeRow& row) const { return row.x_reference * reference_mrays_per_s; }
};

// Measures every setting of trade_settings() on the workload (one engine alive at a time, besides
// the embree16 every pass alternates with, timed with both of its context flags), sets x_anchor and
// marks the Pareto front (highest x_reference for the least error rate) over every measured row: an
// exact Embree row faster than a setting of ours dominates it.
TradeResult run_trade(const Workload& workload, const TradeOptions& options);

// Header and one line per setting (skipped ones included, with empty measurements and the reason).
std::string to_csv(const TradeResult& result);
// The same for a terminal.
report::Table to_table(const TradeResult& result);

}  // namespace beamtrace::workload
