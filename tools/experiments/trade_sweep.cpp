#include "experiments/trade_sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <set>
#include <tuple>

#include "beamtrace/error.hpp"
#include "beamtrace/vlf.hpp"
#include "report/progress_bar.hpp"
#include "experiments/trade_plot.hpp"

namespace beamtrace::workload {

namespace {

constexpr int kMaxPasses = 1000;

std::string number(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

using report::fixed;

std::string kd_settings(const KdBuildRules& r) {
    return "Ct=" + number(r.traversal_cost) + " Ci=" + number(r.intersection_cost) +
           " empty=" + (r.empty_cell_rule ? number(r.empty_cell_min_volume_fraction) : std::string("off")) +
           " flat=" + (r.flat_cell_rule ? "on" : "off") +
           " tiny=" + (r.tiny_cell_rule ? number(r.tiny_cell_min_area_fraction) : std::string("off"));
}

std::string mlrta_settings(const MlrtaSettings& m) {
    return "tile=" + std::to_string(m.initial_tile) + " split=" + std::to_string(m.split_factor) +
           " min=" + std::to_string(m.min_tile) +
           " frustum=" + (m.experimental.frustum_test == FrustumTest::inverse ? "inverse" : "direct") +
           " culling=" + (m.experimental.triangle_culling ? "on" : "off") +
           " ep-triangles=" + (m.experimental.ep_triangles ? "on" : "off") +
           " stuck-stop=" + (m.experimental.stop_when_stuck ? "on" : "off") +
           " stuck-retry=" + (m.experimental.retry_stuck ? "on" : "off") +
           " ep-resume=" + (m.experimental.ep_resume ? "on" : "off") +
           " xp-packets=" + std::to_string(m.experimental.xp_packets);
}

// A named variant of the default settings S: change(s) applied to S{}.
template <class S, class Change>
void add_variant(std::vector<std::pair<std::string, S>>& v, const char* name, Change&& change) {
    S s{};
    change(s);
    v.emplace_back(name, s);
}

// The kd-tree variants: the defaults (the three MLRTA rules on), no rules, each rule off alone,
// and the SAH constants that change the tree's shape.
std::vector<std::pair<std::string, KdBuildRules>> kd_variants() {
    std::vector<std::pair<std::string, KdBuildRules>> v;
    using R = KdBuildRules;
    add_variant(v, "", [](R&) {});
    add_variant(v, " no rules", [](R& r) { r.empty_cell_rule = r.flat_cell_rule = r.tiny_cell_rule = false; });
    add_variant(v, " no rule 1", [](R& r) { r.empty_cell_rule = false; });
    add_variant(v, " no rule 2", [](R& r) { r.flat_cell_rule = false; });
    add_variant(v, " no rule 3", [](R& r) { r.tiny_cell_rule = false; });
    add_variant(v, " empty 0.3", [](R& r) { r.empty_cell_min_volume_fraction = 0.3f; });
    add_variant(v, " Ci 0.1", [](R& r) { r.intersection_cost = 0.1f; });
    add_variant(v, " Ci 1.5", [](R& r) { r.intersection_cost = 1.5f; });  // the default before 2026-12-04
    return v;
}

// MLRTA's beam settings; only the defaults and triangle culling off when the rays form no image
// (the engine then traces packet by packet and the tile settings do nothing).
std::vector<std::pair<std::string, MlrtaSettings>> mlrta_variants(bool image) {
    std::vector<std::pair<std::string, MlrtaSettings>> v;
    using M = MlrtaSettings;
    add_variant(v, "", [](M&) {});
    add_variant(v, " no culling", [](M& m) { m.experimental.triangle_culling = false; });
    if (!image) return v;
    add_variant(v, " no EP triangles", [](M& m) { m.experimental.ep_triangles = false; });
    add_variant(v, " paper schedule", [](M& m) { m.experimental.stop_when_stuck = false; });
    add_variant(v, " no stuck retry", [](M& m) { m.experimental.retry_stuck = false; });
    add_variant(v, " no EP resume", [](M& m) { m.experimental.ep_resume = false; });
    add_variant(v, " direct", [](M& m) { m.experimental.frustum_test = FrustumTest::direct; });
    add_variant(v, " tile 32", [](M& m) { m.initial_tile = 32; });
    add_variant(v, " split 4", [](M& m) { m.split_factor = 4; });
    add_variant(v, " paper packets", [](M& m) {
        m.experimental.xp_packets = 1;
        m.min_tile = 4;
    });
    add_variant(v, " min 32", [](M& m) { m.min_tile = 32; });
    return v;
}

// The parallel subfields the rays of the workload look up with l directions.
std::size_t psfs_needed(const RaySet& rays, int directions) {
    const DirectionSet set(directions);
    std::vector<std::uint8_t> used(std::size_t(set.size()), 0);
    for (std::size_t slot = 0; slot < rays.slots(); ++slot) {
        if (!rays.active(slot)) continue;
        const Float3 d = rays.ray(slot).dir;
        if (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) continue;
        used[set.nearest(d).index] = 1;
    }
    return std::size_t(std::count(used.begin(), used.end(), 1));
}

}  // namespace

bool is_reference_engine(const std::string& engine) { return is_anchor_engine(engine); }

const TradeRow* TradeResult::anchor() const {
    const TradeRow* best = nullptr;
    for (const TradeRow& r : rows)
        if (r.measured() && is_reference_engine(r.setting.engine) && r.x_reference > 0.0 &&
            (!best || r.x_reference > best->x_reference))
            best = &r;
    return best;
}

std::size_t TradeResult::references_on_front() const {
    return std::size_t(std::count_if(
        rows.begin(), rows.end(), [](const TradeRow& r) { return r.pareto && is_reference_engine(r.setting.engine); }));
}

double TradeRow::error_rate() const {
    const std::uint64_t rays = result.oracle.total();
    return rays > 0 ? double(result.oracle.mismatch) / double(rays) : 0.0;
}

std::vector<TradeSetting> trade_settings(const Workload& w, const TradeOptions& options) {
    std::vector<std::string> engines = options.engines;
    if (engines.empty())
        for (const std::string& e : engine_names())
            if (e != "brute" && e != "crsh" && e != "rah" && e != "lists" && e != "lists-flat") engines.push_back(e);
    for (const std::string& e : engines) make_engine(e);  // unknown names fail here
    std::set<std::string> wanted(engines.begin(), engines.end());
    if (options.anchor_engines) wanted.insert(anchor_engines().begin(), anchor_engines().end());

    std::vector<TradeSetting> out;
    const EngineOptions base;
    const auto add = [&](const std::string& engine, const std::string& settings, const std::string& label,
                         const EngineOptions& o) {
        if (wanted.count(engine)) out.push_back({engine, settings, label, o, {}});
    };
    add("embree1", "reference", "embree1", base);
    add("embree16", "reference", "embree16", base);
    add("embree-stream", "reference", "embree-stream", base);
    for (const auto& [suffix, rules] : kd_variants()) {
        EngineOptions o = base;
        o.kd_rules = rules;
        add("kd1", kd_settings(rules), "kd1" + suffix, o);
    }
    for (const auto& [suffix, m] : mlrta_variants(false)) {
        EngineOptions o = base;
        o.mlrta = m;
        add("kd16", kd_settings(o.kd_rules) + " culling=" + (m.experimental.triangle_culling ? "on" : "off"),
            "kd16" + suffix, o);
    }
    for (const auto& [suffix, m] : mlrta_variants(w.rays.packets_x > 0)) {
        EngineOptions o = base;
        o.mlrta = m;
        add("mlrta", kd_settings(o.kd_rules) + " " + mlrta_settings(m), "mlrta" + suffix, o);
    }
    // The stream tracer: sorted and grouped (default), with larger groups only, and unsorted (every
    // ray alone: what sorting buys); Embree on its sorted order.
    for (const auto& [label, sort, min_group] :
         {std::tuple{"stream", true, 4}, std::tuple{"stream min 8", true, 8}, std::tuple{"stream unsorted", false, 4}}) {
        EngineOptions o = base;
        o.stream.sort = sort;
        o.stream.min_group_rays = min_group;
        add("stream", std::string("sort=") + (sort ? "on" : "off") + " min_group=" + std::to_string(min_group), label,
            o);
    }
    add("embree-sorted", "the stream tracer's order (sort untimed)", "embree-sorted", base);
    const double triangles = double(w.source.scene.triangle_count());
    for (const char* engine : {"vlf", "vlf-fast"}) {
        if (!wanted.count(engine)) continue;
        for (int l : {33, 129, 513}) {
            const std::size_t psfs = psfs_needed(w.rays, l);
            std::string skipped;
            if (triangles * double(psfs) > options.vlf_budget)
                skipped = "skipped: the rays need " + std::to_string(psfs) + " of " + std::to_string(l) + " PSFs; " +
                          std::to_string(psfs) + " x " + std::to_string(std::size_t(triangles)) +
                          " triangles is over the budget of " + number(options.vlf_budget / 1e6) +
                          " million triangle-PSFs";
            for (int n : {64, 128})
                for (int d : {0, 4}) {
                    EngineOptions o = base;
                    o.vlf.directions = l;
                    o.vlf.tiles = n;
                    o.vlf.depth = d;
                    add(engine, "l=" + std::to_string(l) + " n=" + std::to_string(n) + " d=" + std::to_string(d),
                        std::string(engine) + " " + std::to_string(l) + "/" + std::to_string(n) + "/" +
                            std::to_string(d),
                        o);
                    out.back().skipped = skipped;
                }
            // Under memory budgets: lazy tiles, the least recently used freed (docs/vlf.md).
            if (std::string(engine) != "vlf") continue;
            for (std::size_t memory : options.vlf_memory) {
                if (memory == 0) continue;
                EngineOptions o = base;
                o.vlf.directions = l;
                o.vlf.memory_budget_bytes = memory;
                const std::string mib = number(double(memory) / double(1 << 20)) + "M";
                add(engine, "l=" + std::to_string(l) + " n=128 d=4 memory=" + mib,
                    "vlf " + std::to_string(l) + "/128/4 " + mib, o);
                const std::size_t fixed = VisibilityField::fixed_memory_bytes(w.source.scene.triangle_count(), o.vlf);
                out.back().skipped = skipped;
                if (skipped.empty() && memory < fixed + (std::size_t(1) << 16))
                    out.back().skipped = "skipped: the budget is below the field's fixed part of " +
                                         number(double(fixed) / double(1 << 20)) + " MiB";
            }
        }
    }
    return out;
}

TradeResult run_trade(const Workload& w, const TradeOptions& options) {
    const std::vector<TradeSetting> settings = trade_settings(w, options);
    TradeResult result;
    result.scene = w.source.name;
    result.triangles = w.source.scene.triangle_count();
    result.mode = w.mode;
    result.order = w.order;
    result.lights = point_lights(w);
    result.area_light = w.mode == Mode::shadow && w.lights.area.has_value();
    result.width = w.rays.width;
    result.height = w.rays.height;
    result.threads = options.threads;
    result.repeats = options.repeats;
    result.min_seconds = options.min_seconds;
    result.rays = w.rays.ray_count;
    const std::size_t measured = std::size_t(
        std::count_if(settings.begin(), settings.end(), [](const TradeSetting& s) { return s.skipped.empty(); }));
    BenchOptions reference_options;
    reference_options.threads = options.threads;
    TimedEngine reference = build_engine(w, "embree16", reference_options);
    double reference_best = 1e300;
    std::size_t done = 0;
    for (const TradeSetting& s : settings) {
        TradeRow row;
        row.setting = s;
        row.result.name = s.engine;
        if (s.skipped.empty()) {
            BenchOptions bo;
            bo.threads = options.threads;
            bo.repeats = options.repeats;
            bo.engine_options = s.options;
            bo.progress = options.progress;
            char counter[64];
            std::snprintf(counter, sizeof counter, "[%zu/%zu] ", ++done, measured);
            bo.progress_label = counter + s.label;
            TimedEngine t = build_engine(w, s.engine, bo);
            reference.result.seconds = 1e300;
            {
                report::ProgressBar bar("trace " + bo.progress_label, options.progress && report::stderr_is_terminal());
                const auto start = std::chrono::steady_clock::now();
                double elapsed = 0.0;
                for (int i = 0; i < options.repeats || (elapsed < options.min_seconds && i < kMaxPasses); ++i) {
                    time_once(w, t, options.threads);
                    time_once(w, reference, options.threads);
                    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                    bar.update(std::min(double(i + 1) / options.repeats,
                                        options.min_seconds > 0.0 ? elapsed / options.min_seconds : 1.0));
                }
                bar.finish();
            }
            summarize_timing(w, t);
            reference_best = std::min(reference_best, reference.result.seconds);
            row.x_reference = t.result.seconds > 0.0 ? reference.result.seconds / t.result.seconds : 0.0;
            row.result = std::move(t.result);
            row.result.oracle = compare_with_oracle(w, t.answers, true);
            if (closest_hit(w.mode)) row.t_error = relative_t_error(t.answers.hits, w.reference_hits);
            if (w.mode == Mode::ao)
                row.occlusion_mae = occlusion_fraction_mae(w.rays.pixel, t.answers.occluded, w.reference_occluded);
        }
        result.rows.push_back(std::move(row));
    }
    if (reference_best < 1e300 && reference_best > 0.0)
        result.reference_mrays_per_s = double(w.rays.ray_count) / reference_best / 1e6;
    if (const TradeRow* anchor = result.anchor()) {
        const double a = anchor->x_reference;
        for (TradeRow& r : result.rows)
            if (r.measured()) r.x_anchor = r.x_reference / a;
    }
    std::vector<std::size_t> candidates;
    std::vector<double> errors, speeds;
    for (std::size_t i = 0; i < result.rows.size(); ++i) {
        const TradeRow& r = result.rows[i];
        if (!r.measured()) continue;
        candidates.push_back(i);
        errors.push_back(r.error_rate());
        speeds.push_back(r.x_reference);
    }
    for (std::size_t k : pareto_front(errors, speeds)) result.rows[candidates[k]].pareto = true;
    return result;
}

namespace {

// A text field of the CSV: commas (the separator; the file has no quoting) become semicolons.
std::string csv_text(std::string text) {
    std::replace(text.begin(), text.end(), ',', ';');
    return text;
}

}  // namespace

std::string to_csv(const TradeResult& r) {
    std::string csv =
        "engine,settings,mrays_per_s,x_embree16,trace_seconds,build_seconds,memory_bytes,rays,agree,ties,grazing,"
        "mismatch,"
        "error_rate,mean_rel_t_error,max_rel_t_error,ao_occlusion_mae,pareto,note,x_anchor\n";
    for (const TradeRow& row : r.rows) {
        csv += row.setting.engine + "," + csv_text(row.setting.settings) + ",";
        if (!row.measured()) {
            csv += ",,,,,,,,,,,,,,0," + csv_text(row.setting.skipped) + ",\n";
            continue;
        }
        const EngineResult& e = row.result;
        const bool closest = closest_hit(r.mode);  // hit distances compared (primary, diffuse)
        csv += number(e.mrays_per_s) + "," + number(row.x_reference) + "," + number(e.seconds) + "," +
               number(e.build_seconds) + "," + std::to_string(e.memory_bytes) + "," + std::to_string(e.oracle.total()) +
               "," + std::to_string(e.oracle.agree) + "," + std::to_string(e.oracle.ties) + "," +
               std::to_string(e.oracle.grazing) + "," + std::to_string(e.oracle.mismatch) + "," +
               number(row.error_rate()) + "," + (closest ? number(row.t_error.mean) : "") + "," +
               (closest ? number(row.t_error.max) : "") + "," + (r.mode == Mode::ao ? number(row.occlusion_mae) : "") +
               "," + (row.pareto ? "1" : "0") + "," + (is_reference_engine(row.setting.engine) ? "reference" : "") +
               "," + (r.anchor() ? number(row.x_anchor) : "") + "\n";
    }
    return csv;
}

report::Table to_table(const TradeResult& r) {
    const bool closest = closest_hit(r.mode), ao = r.mode == Mode::ao;
    report::Table t({"setting", "Mrays/s", "x embree16", "x anchor", "build s", "memory MB", "mismatch", "error %",
                     closest ? "mean |dt|/t" : (ao ? "AO MAE" : "-"), "Pareto"});
    for (const TradeRow& row : r.rows) {
        if (!row.measured()) {
            t.add_row({row.setting.label, "-", "-", "-", "-", "-", "-", "-", "-", "skipped"});
            continue;
        }
        const EngineResult& e = row.result;
        const bool is_anchor = &row == r.anchor();
        t.add_row({row.setting.label + (is_anchor ? " (anchor)" : ""), fixed(e.mrays_per_s, 3),
                   fixed(row.x_reference, 2), r.anchor() ? fixed(row.x_anchor, 2) : "-", fixed(e.build_seconds, 3),
                   fixed(double(e.memory_bytes) / 1e6, 1), std::to_string(e.oracle.mismatch),
                   number(100.0 * row.error_rate()),
                   closest ? number(row.t_error.mean) : (ao ? number(row.occlusion_mae) : "-"), row.pareto ? "*" : ""});
    }
    return t;
}

}  // namespace beamtrace::workload
