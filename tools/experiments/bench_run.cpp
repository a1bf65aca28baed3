#include "experiments/bench_run.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "beamtrace/error.hpp"
#include "oracle/comparison_json.hpp"
#include "report/progress_bar.hpp"

namespace beamtrace::workload {

namespace {

oracle::Tally compare(const Workload& w, const std::vector<Hit>& hits) {
    oracle::Tally tally;
    for (std::size_t slot = 0; slot < w.rays.slots(); ++slot)
        if (w.rays.active(slot))
            tally.record_hit(w.source.scene, slot, w.rays.ray(slot), hits[slot], w.reference_hits[slot]);
    return tally;
}

oracle::Tally compare(const Workload& w, const std::vector<std::uint8_t>& occluded, bool oracle_hints = false) {
    oracle::Tally tally;
    for (std::size_t slot = 0; slot < w.rays.slots(); ++slot) {
        if (!w.rays.active(slot)) continue;
        const Ray ray = w.rays.ray(slot);
        const bool ours = occluded[slot] != 0, reference = w.reference_occluded[slot] != 0;
        std::uint32_t hint = kNoHit;
        if (oracle_hints && reference && !ours) hint = w.oracle->intersect1(ray).triangle;
        tally.record_occlusion(w.source.scene, slot, ray, ours, reference, hint);
    }
    return tally;
}

std::uint64_t count_hits(const std::vector<Hit>& hits) {
    std::uint64_t n = 0;
    for (const Hit& h : hits) n += h.hit();
    return n;
}

std::uint64_t count_hits(const std::vector<std::uint8_t>& occluded) {
    std::uint64_t n = 0;
    for (std::uint8_t o : occluded) n += o;
    return n;
}

using report::fixed;

}  // namespace

oracle::Tally check_against_oracle(const Engine& engine, const Workload& w, int threads) {
    if (closest_hit(w.mode)) {
        std::vector<Hit> hits;
        engine.intersect(w.rays, hits, threads);
        return compare(w, hits);
    }
    std::vector<std::uint8_t> occluded;
    engine.occluded(w.rays, occluded, threads);
    return compare(w, occluded);
}

namespace {

std::string progress_label(const std::string& name, const BenchOptions& options) {
    return options.progress_label.empty() ? name : options.progress_label;
}

void check_options(const BenchOptions& options) {
    if (options.repeats < 1) throw Error("repeats must be at least 1");
    if (options.threads < 1 || options.threads > 1024) throw Error("--threads must be between 1 and 1024");
}

EngineResult finish(const Workload& w, TimedEngine& run) {
    summarize_timing(w, run);
    EngineResult& r = run.result;
    r.oracle = compare_with_oracle(w, run.answers);
    r.stats = stats_with_variants(*run.engine, r, w.rays);
    return r;
}

double mrays(const Workload& w, double seconds) {
    return seconds > 0.0 && seconds < 1e300 ? double(w.rays.ray_count) / seconds / 1e6 : 0.0;
}

// The engines of a run: the given ones, then the anchor engines missing from them (if asked).
std::vector<std::string> engines_of_run(const BenchOptions& options) {
    std::vector<std::string> engines = options.engines;
    if (options.anchor_engines)
        for (const std::string& a : anchor_engines())
            if (std::find(engines.begin(), engines.end(), a) == engines.end()) engines.push_back(a);
    return engines;
}

}  // namespace

oracle::Tally compare_with_oracle(const Workload& w, const EngineAnswers& answers, bool oracle_hints) {
    return closest_hit(w.mode) ? compare(w, answers.hits) : compare(w, answers.occluded, oracle_hints);
}

const std::vector<std::string>& anchor_engines() {
    static const std::vector<std::string> names = {"embree1", "embree16", "embree-stream"};
    return names;
}

bool is_anchor_engine(const std::string& engine) {
    const auto& a = anchor_engines();
    return std::find(a.begin(), a.end(), engine) != a.end();
}

TimedEngine build_engine(const Workload& w, const std::string& name, const BenchOptions& options) {
    check_options(options);
    TimedEngine run;
    run.engine = make_engine(name);
    run.result.name = name;
    run.result.seconds = 1e300;
    for (const std::string& v : run.engine->timing_variants()) run.result.variants.push_back({v});
    run.result.variant_key = run.engine->timing_variant_key();
    report::ProgressBar bar("build " + progress_label(name, options), options.progress && report::stderr_is_terminal());
    EngineOptions eo = options.engine_options;
    eo.object_of_triangle = w.source.object_of_triangle;
    eo.embree_scene = w.oracle;  // the Embree engines trace the oracle's scene when built alike
    if (bar.enabled()) eo.build_progress = [&bar](double f) { bar.update(f); };
    run.engine->build(w.source.scene, eo);
    bar.finish();
    run.engine->prepare(w.rays);
    return run;
}

void time_once(const Workload& w, TimedEngine& run, int threads) {
    EngineResult& r = run.result;
    if (r.variants.empty()) {
        r.seconds = std::min(r.seconds, run.engine->timed_pass(w.rays, run.answers, threads, 0));
        return;
    }
    for (std::size_t v = 0; v < r.variants.size(); ++v) {
        const double s = run.engine->timed_pass(w.rays, run.answers, threads, int(v));
        r.variants[v].seconds = std::min(r.variants[v].seconds, s);
        r.seconds = std::min(r.seconds, s);
    }
}

nlohmann::json stats_with_variants(const Engine& engine, const EngineResult& r, const RaySet& rays) {
    nlohmann::json stats = engine.stats(rays);
    if (r.variants.empty()) return stats;
    const VariantTiming* best = &r.variants.front();
    for (const VariantTiming& v : r.variants) {
        stats[v.name + "_mrays_per_s"] = v.mrays_per_s;
        if (v.seconds < best->seconds) best = &v;
    }
    stats[r.variant_key] = best->name;
    return stats;
}

std::optional<Anchor> find_anchor(std::vector<EngineResult>& results) {
    const EngineResult* best = nullptr;
    for (const EngineResult& e : results)
        if (is_anchor_engine(e.name) && e.mrays_per_s > 0.0 && (!best || e.mrays_per_s > best->mrays_per_s)) best = &e;
    if (!best) {
        for (EngineResult& e : results) e.x_anchor = 0.0;
        return std::nullopt;
    }
    Anchor a{best->name, best->mrays_per_s, {}};
    if (best->stats.is_object() && best->stats.contains(best->variant_key) &&
        best->stats[best->variant_key].is_string())
        a.context_flag = best->stats[best->variant_key].get<std::string>();
    for (EngineResult& e : results) e.x_anchor = e.mrays_per_s / a.mrays_per_s;
    return a;
}

void summarize_timing(const Workload& w, TimedEngine& run) {
    EngineResult& r = run.result;
    // Read after tracing: engines that build parts of their structure on first use (vlf) count them.
    r.build_seconds = run.engine->build_seconds();
    r.memory_bytes = run.engine->memory_bytes();
    r.mrays_per_s = mrays(w, r.seconds);
    for (VariantTiming& v : r.variants) v.mrays_per_s = mrays(w, v.seconds);
    r.hits = closest_hit(w.mode) ? count_hits(run.answers.hits) : count_hits(run.answers.occluded);
}

BenchResult run_bench(const Workload& w, const BenchOptions& options) {
    if (options.engines.empty()) throw Error("no engines given (--engines)");
    check_options(options);
    const std::vector<std::string> engines = engines_of_run(options);
    for (const std::string& name : engines) make_engine(name);  // unknown names fail before any work
    BenchResult result;
    result.scene = w.source.name;
    result.triangles = w.source.scene.triangle_count();
    result.mode = w.mode;
    result.order = w.order;
    result.lights = point_lights(w);
    result.area_light = w.mode == Mode::shadow && w.lights.area.has_value();
    result.width = w.rays.width;
    result.height = w.rays.height;
    result.threads = options.threads;
    result.rays = w.rays.ray_count;
    // Every engine is built first, then the timed passes go round the engines in turn, so that a
    // change of machine load during the run affects every engine alike (the ratios stay fair).
    std::vector<TimedEngine> runs;
    for (const std::string& name : engines) runs.push_back(build_engine(w, name, options));
    report::ProgressBar bar("trace", options.progress && report::stderr_is_terminal());
    const double passes = double(options.repeats) * double(runs.size());
    double done = 0;
    for (int i = 0; i < options.repeats; ++i)
        for (TimedEngine& run : runs) {
            time_once(w, run, options.threads);
            bar.update(++done / passes);
        }
    bar.finish();
    for (TimedEngine& run : runs) result.engines.push_back(finish(w, run));
    result.anchor = find_anchor(result.engines);
    return result;
}

nlohmann::json to_json(const BenchResult& r) {
    nlohmann::json engines = nlohmann::json::object();
    for (const EngineResult& e : r.engines) {
        engines[e.name] = {{"mrays_per_s", e.mrays_per_s},
                           {"seconds", e.seconds},
                           {"build_seconds", e.build_seconds},
                           {"memory_bytes", e.memory_bytes},
                           {"hits", e.hits},
                           {"oracle", oracle::to_json(e.oracle)},
                           {"stats", e.stats}};
        engines[e.name]["x_anchor"] = r.anchor ? nlohmann::json(e.x_anchor) : nlohmann::json(nullptr);
    }
    nlohmann::json anchor = nullptr;
    if (r.anchor)
        anchor = {{"engine", r.anchor->engine},
                  {"mrays_per_s", r.anchor->mrays_per_s},
                  {"context_flag", r.anchor->context_flag}};
    return {{"scene", r.scene},
            {"triangles", r.triangles},
            {"mode", to_string(r.mode)},
            {"width", r.width},
            {"height", r.height},
            {"threads", r.threads},
            {"rays", r.rays},
            {"anchor", anchor},
            {"engines", engines},
            {"order", to_string(r.order)},
            {"lights", r.lights},
            {"area_light", r.area_light}};
}

report::Table to_table(const BenchResult& r) {
    report::Table t({"engine", "Mrays/s", "x best Embree", "trace s", "build s", "memory MB", "hits", "agree", "ties",
                     "grazing", "mismatch"});
    for (const EngineResult& e : r.engines) {
        std::string name = e.name;
        if (r.anchor && e.name == r.anchor->engine) name += " (anchor)";
        t.add_row({name, fixed(e.mrays_per_s, 3), r.anchor ? fixed(e.x_anchor, 2) : "-", fixed(e.seconds, 3),
                   fixed(e.build_seconds, 3), fixed(double(e.memory_bytes) / 1e6, 1), std::to_string(e.hits),
                   std::to_string(e.oracle.agree), std::to_string(e.oracle.ties), std::to_string(e.oracle.grazing),
                   std::to_string(e.oracle.mismatch)});
    }
    return t;
}

}  // namespace beamtrace::workload
