// Single-ray traversal: the kd-tree (KdTree::intersect for primary rays, KdTree::occluded for shadow
// rays) against Embree 3 (rtcIntersect1 / rtcOccluded1 and rtcIntersect16 / rtcOccluded16 through
// oracle::EmbreeOracle, robust mode) on the same rays: 256x256 primary rays from the scene's default
// camera and one shadow ray per primary hit towards the default light.
//
// Per scene, the kd-tree, the Embree scene and the rays are built once, on first use, in a static
// cache (never timed). items_processed = rays, so Google Benchmark prints rays per second. Every
// benchmark reports hit_rate (rays that hit, or are occluded); the kd benchmarks also report
// tests_per_ray (ray/triangle tests), leaves_per_ray, steps_per_ray (inner nodes) and vs_embree1 = kd rays/s divided by
// the rays/s of the Embree single-ray benchmark of the same scene and mode, measured in this process (it is registered,
// and so run, just before; if a filter left it out, its rate is measured in the kd benchmark's set-up). Both rates are
// rays per second of thread CPU time, as in Google Benchmark's items_per_second.
#include <benchmark/benchmark.h>

#include <time.h>

#include <bit>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/kdtree.hpp"
#include "simd/isa.hpp"
#include "rays/workload.hpp"

#ifndef BEAMTRACE_SCENES_DIR
#error "BEAMTRACE_SCENES_DIR must name the folder of the shared scene files"
#endif

namespace {

using beamtrace::Hit;
using beamtrace::KdTree;
using beamtrace::Packet16;
using beamtrace::PacketHits16;
using beamtrace::Ray;
namespace workload = beamtrace::workload;

constexpr int kImageSize = 256;
const char* const kScenes[] = {"bunny", "room", "tetra:6"};

enum Mode { kPrimary = 0, kShadow = 1 };
const char* mode_name(Mode m) { return m == kPrimary ? "primary" : "shadow"; }

double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// The rays of one mode: active lanes only for single-ray queries, the non-empty packets for Embree's
// 16-wide queries.
struct Rays {
    std::vector<Ray> single;
    std::vector<Packet16> packets;
    // Per ray, in the kd-tree: ray/triangle tests, leaves and inner nodes visited.
    double tests_per_ray = 0, leaves_per_ray = 0, steps_per_ray = 0;
};

struct SceneCase {
    std::string error;  // set when the scene cannot be loaded: every benchmark of it is skipped
    std::string description;
    std::optional<workload::Workload> work;
    std::optional<KdTree> tree;
    Rays rays[2];                               // kPrimary, kShadow
    double embree1_rate[2] = {0, 0};            // rays/s of the last Embree single-ray run, per mode (0: none yet)
    bool embree1_in_setup[2] = {false, false};  // that rate was measured by the kd benchmark itself
};

Rays collect(const workload::RaySet& set, const KdTree& tree, Mode mode) {
    Rays r;
    for (const Packet16& p : set.packets)
        if (p.active != 0) r.packets.push_back(p);  // shadow sets keep empty packets where nothing was hit
    beamtrace::QueryCounters counters;
    for (std::size_t slot = 0; slot < set.slots(); ++slot)
        if (set.active(slot)) r.single.push_back(set.ray(slot));
    const beamtrace::QueryOptions counting{1, &counters};
    if (mode == kPrimary) {
        std::vector<Hit> hits(r.single.size());
        tree.intersect(r.single, hits, counting);
    } else {
        std::vector<std::uint8_t> occluded(r.single.size());
        tree.occluded(r.single, occluded, counting);
    }
    if (!r.single.empty()) {
        const double n = double(r.single.size());
        r.tests_per_ray = double(counters.triangle_tests) / n;
        r.leaves_per_ray = double(counters.leaves) / n;
        r.steps_per_ray = double(counters.inner_steps) / n;
    }
    return r;
}

std::unique_ptr<SceneCase> build_case(const std::string& name) {
    auto c = std::make_unique<SceneCase>();
    std::string spec = name;
    if (name == "bunny") {
        spec = std::string(BEAMTRACE_SCENES_DIR) + "/bunny00.off";
        if (!std::filesystem::exists(spec)) {
            c->error = "scene file " + spec + " is absent: bunny benchmarks skipped";
            return c;
        }
    }
    try {
        workload::WorkloadConfig config;
        config.scene = spec;
        config.mode = workload::Mode::shadow;
        config.width = kImageSize;
        config.height = kImageSize;
        c->work.emplace(workload::make_workload(config));
        c->tree.emplace(KdTree::build(c->work->source.scene));
        c->rays[kPrimary] = collect(c->work->primary, *c->tree, kPrimary);
        c->rays[kShadow] = collect(c->work->rays, *c->tree, kShadow);
        c->description = std::to_string(c->work->source.scene.triangle_count()) + " triangles";
    } catch (const std::exception& e) {
        c->error = "scene " + name + ": " + e.what();
    }
    return c;
}

SceneCase& scene_case(const std::string& name) {
    static std::map<std::string, std::unique_ptr<SceneCase>> cache;
    auto& slot = cache[name];
    if (!slot) slot = build_case(name);
    return *slot;
}

// One pass of Embree's single-ray queries over the rays; returns the rays that hit (or are occluded).
std::uint64_t embree1_pass(const SceneCase& c, Mode mode) {
    const beamtrace::oracle::EmbreeOracle& oracle = *c.work->oracle;
    std::uint64_t hits = 0;
    if (mode == kPrimary) {
        for (const Ray& r : c.rays[mode].single) hits += oracle.intersect1(r).hit();
    } else {
        for (const Ray& r : c.rays[mode].single) hits += oracle.occluded1(r);
    }
    return hits;
}

// Common ending: rays per second, hit rate, and the rate in rays per thread CPU second.
double finish(benchmark::State& state, std::size_t rays_per_pass, std::uint64_t hits, double cpu_seconds) {
    const double rays = double(state.iterations()) * double(rays_per_pass);
    state.SetItemsProcessed(std::int64_t(rays));
    state.counters["hit_rate"] = rays > 0 ? double(hits) / rays : 0.0;
    return cpu_seconds > 0 ? rays / cpu_seconds : 0.0;
}

bool usable(benchmark::State& state, const SceneCase& c) {
    if (c.error.empty()) return true;
    state.SkipWithError(c.error.c_str());
    return false;
}

void bm_embree1(benchmark::State& state, const std::string& name, Mode mode) {
    SceneCase& c = scene_case(name);
    if (!usable(state, c)) return;
    std::uint64_t hits = 0;
    const double start = thread_cpu_seconds();
    for (auto _ : state) {
        hits += embree1_pass(c, mode);
        benchmark::DoNotOptimize(hits);
    }
    const double cpu = thread_cpu_seconds() - start;
    c.embree1_rate[mode] = finish(state, c.rays[mode].single.size(), hits, cpu);
    c.embree1_in_setup[mode] = false;
    state.SetLabel("Embree robust, " + c.description);
}

void bm_kd(benchmark::State& state, const std::string& name, Mode mode) {
    SceneCase& c = scene_case(name);
    if (!usable(state, c)) return;
    std::string label = std::string("kd-tree, ") + beamtrace::isa_name(beamtrace::best_isa()) + " kernels";
    if (c.embree1_rate[mode] <= 0) {
        // The Embree benchmark did not run: measure its rate here, untimed by Google Benchmark.
        std::uint64_t passes = 0, hits = 0;
        const double start = thread_cpu_seconds();
        double cpu = 0;
        while (cpu < 0.2) {
            hits += embree1_pass(c, mode);
            ++passes;
            cpu = thread_cpu_seconds() - start;
        }
        benchmark::DoNotOptimize(hits);
        c.embree1_rate[mode] = double(passes) * double(c.rays[mode].single.size()) / cpu;
        c.embree1_in_setup[mode] = true;
    }
    if (c.embree1_in_setup[mode]) label += " (Embree rate measured in set-up)";
    const KdTree& tree = *c.tree;
    const std::vector<Ray>& rays = c.rays[mode].single;
    std::uint64_t hits = 0;
    const double start = thread_cpu_seconds();
    for (auto _ : state) {
        if (mode == kPrimary) {
            for (const Ray& r : rays) hits += tree.intersect(r).hit();
        } else {
            for (const Ray& r : rays) hits += tree.occluded(r);
        }
        benchmark::DoNotOptimize(hits);
    }
    const double cpu = thread_cpu_seconds() - start;
    const double rate = finish(state, rays.size(), hits, cpu);
    state.counters["tests_per_ray"] = c.rays[mode].tests_per_ray;
    state.counters["leaves_per_ray"] = c.rays[mode].leaves_per_ray;
    state.counters["steps_per_ray"] = c.rays[mode].steps_per_ray;
    state.counters["vs_embree1"] = rate / c.embree1_rate[mode];
    state.SetLabel(label + ", " + c.description);
}

void bm_embree16(benchmark::State& state, const std::string& name, Mode mode) {
    SceneCase& c = scene_case(name);
    if (!usable(state, c)) return;
    const beamtrace::oracle::EmbreeOracle& oracle = *c.work->oracle;
    const std::vector<Packet16>& packets = c.rays[mode].packets;
    PacketHits16 out;
    std::uint64_t hits = 0;
    for (auto _ : state) {
        for (const Packet16& p : packets) {
            if (mode == kPrimary) {
                oracle.intersect16(p, out);
                for (int i = 0; i < 16; ++i) hits += out.triangle[i] != beamtrace::kNoHit;
            } else {
                hits += unsigned(std::popcount(oracle.occluded16(p)));
            }
        }
        benchmark::DoNotOptimize(hits);
    }
    finish(state, c.rays[mode].single.size(), hits, 0.0);
    state.SetLabel("Embree robust, 16-wide, " + c.description);
}

void register_benchmarks() {
    for (const char* scene : kScenes) {
        const std::string name = scene;
        for (Mode mode : {kPrimary, kShadow}) {
            const std::string prefix = std::string(mode_name(mode)) + "/" + name + "/";
            const char* query = mode == kPrimary ? "intersect" : "occluded";
            benchmark::RegisterBenchmark((prefix + "embree_" + query + "1").c_str(),
                                         [name, mode](benchmark::State& s) { bm_embree1(s, name, mode); });
            benchmark::RegisterBenchmark((prefix + "kd_" + query).c_str(),
                                         [name, mode](benchmark::State& s) { bm_kd(s, name, mode); });
            benchmark::RegisterBenchmark((prefix + "embree_" + query + "16").c_str(),
                                         [name, mode](benchmark::State& s) { bm_embree16(s, name, mode); });
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    register_benchmarks();
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
