#include "workload/bench_run.hpp"

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
        if (w.rays.active(slot)) tally.record_hit(w.source.scene, slot, w.rays.ray(slot), hits[slot], w.reference_hits[slot]);
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

std::string fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

}  // namespace

oracle::Tally check_against_oracle(const Engine& engine, const Workload& w, int threads) {
    if (w.mode == Mode::primary) {
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
    r.stats = run.engine->stats(w.rays);
    return r;
}

}  // namespace

oracle::Tally compare_with_oracle(const Workload& w, const EngineAnswers& answers, bool oracle_hints) {
    return w.mode == Mode::primary ? compare(w, answers.hits) : compare(w, answers.occluded, oracle_hints);
}

TimedEngine build_engine(const Workload& w, const std::string& name, const BenchOptions& options) {
    check_options(options);
    TimedEngine run;
    run.engine = make_engine(name);
    run.result.name = name;
    run.result.seconds = 1e300;
    report::ProgressBar bar("build " + progress_label(name, options), options.progress && report::stderr_is_terminal());
    EngineOptions eo = options.engine_options;
    if (bar.enabled()) eo.build_progress = [&bar](double f) { bar.update(f); };
    run.engine->build(w.source.scene, eo);
    bar.finish();
    return run;
}

void time_once(const Workload& w, TimedEngine& run, int threads) {
    const auto start = std::chrono::steady_clock::now();
    if (w.mode == Mode::primary) run.engine->intersect(w.rays, run.answers.hits, threads);
    else run.engine->occluded(w.rays, run.answers.occluded, threads);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.result.seconds = std::min(run.result.seconds, s);
}

void summarize_timing(const Workload& w, TimedEngine& run) {
    EngineResult& r = run.result;
    // Read after tracing: engines that build parts of their structure on first use (vlf) count them.
    r.build_seconds = run.engine->build_seconds();
    r.memory_bytes = run.engine->memory_bytes();
    r.mrays_per_s = r.seconds > 0.0 ? double(w.rays.ray_count) / r.seconds / 1e6 : 0.0;
    r.hits = w.mode == Mode::primary ? count_hits(run.answers.hits) : count_hits(run.answers.occluded);
}

EngineResult run_engine(const Workload& w, const std::string& name, const BenchOptions& options) {
    if (options.repeats < 1) throw Error("repeats must be at least 1");
    if (options.threads < 1 || options.threads > 1024) throw Error("--threads must be between 1 and 1024");
    std::unique_ptr<Engine> engine = make_engine(name);
    EngineResult r;
    r.name = name;
    {
        report::ProgressBar bar("build " + name, options.progress && report::stderr_is_terminal());
        EngineOptions eo = options.engine_options;
        if (bar.enabled()) eo.build_progress = [&bar](double f) { bar.update(f); };
        engine->build(w.source.scene, eo);
        bar.finish();
    }

    const bool closest = w.mode == Mode::primary;
    std::vector<Hit> hits;
    std::vector<std::uint8_t> occluded;
    r.seconds = 1e300;
    report::ProgressBar bar("trace " + name, options.progress && report::stderr_is_terminal());
    for (int run = 0; run < options.repeats; ++run) {
        const auto start = std::chrono::steady_clock::now();
        if (closest) engine->intersect(w.rays, hits, options.threads);
        else engine->occluded(w.rays, occluded, options.threads);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        r.seconds = std::min(r.seconds, s);
        bar.update(double(run + 1) / options.repeats);
    }
    bar.finish();
    // Read after tracing: engines that build parts of their structure on first use (vlf) count them.
    r.build_seconds = engine->build_seconds();
    r.memory_bytes = engine->memory_bytes();
    r.mrays_per_s = r.seconds > 0.0 ? double(w.rays.ray_count) / r.seconds / 1e6 : 0.0;
    r.hits = closest ? count_hits(hits) : count_hits(occluded);
    r.oracle = closest ? compare(w, hits) : compare(w, occluded);
    r.stats = engine->stats(w.rays);
    return r;
}

BenchResult run_bench(const Workload& w, const BenchOptions& options) {
    if (options.engines.empty()) throw Error("no engines given (--engines)");
    check_options(options);
    for (const std::string& name : options.engines) make_engine(name);  // unknown names fail before any work
    BenchResult result;
    result.scene = w.source.name;
    result.triangles = w.source.scene.triangle_count();
    result.mode = w.mode;
    result.width = w.rays.width;
    result.height = w.rays.height;
    result.threads = options.threads;
    result.rays = w.rays.ray_count;
    // Every engine is built first, then the timed passes go round the engines in turn, so that a
    // change of machine load during the run affects every engine alike (the ratios stay fair).
    std::vector<TimedEngine> runs;
    for (const std::string& name : options.engines) runs.push_back(build_engine(w, name, options));
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
    return result;
}

nlohmann::json to_json(const BenchResult& r) {
    nlohmann::json engines = nlohmann::json::object();
    for (const EngineResult& e : r.engines) {
        engines[e.name] = {{"mrays_per_s", e.mrays_per_s},     {"seconds", e.seconds},
                           {"build_seconds", e.build_seconds}, {"memory_bytes", e.memory_bytes},
                           {"hits", e.hits},                   {"oracle", oracle::to_json(e.oracle)},
                           {"stats", e.stats}};
    }
    return {{"scene", r.scene}, {"triangles", r.triangles}, {"mode", to_string(r.mode)}, {"width", r.width},
            {"height", r.height}, {"threads", r.threads}, {"rays", r.rays}, {"engines", engines}};
}

report::Table to_table(const BenchResult& r) {
    const EngineResult* base = nullptr;
    for (const char* name : {"embree1", "embree16"})
        for (const EngineResult& e : r.engines)
            if (!base && e.name == name) base = &e;
    report::Table t({"engine", "Mrays/s", base ? "x " + base->name : "x embree", "trace s", "build s", "memory MB",
                     "hits", "agree", "ties", "grazing", "mismatch"});
    for (const EngineResult& e : r.engines) {
        t.add_row({e.name, fixed(e.mrays_per_s, 3), base ? fixed(e.mrays_per_s / base->mrays_per_s, 2) : "-",
                   fixed(e.seconds, 3), fixed(e.build_seconds, 3), fixed(double(e.memory_bytes) / 1e6, 1),
                   std::to_string(e.hits), std::to_string(e.oracle.agree), std::to_string(e.oracle.ties),
                   std::to_string(e.oracle.grazing), std::to_string(e.oracle.mismatch)});
    }
    return t;
}

}  // namespace beamtrace::workload
