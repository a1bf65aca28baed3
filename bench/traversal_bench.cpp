// Single-ray traversal: the kd-tree (KdTree::intersect for primary rays, KdTree::occluded for shadow
// rays) against Embree 3 at its documented best (oracle::EmbreeNativeRays: rays prebuilt in Embree's
// layouts, rtcIntersect1 / rtcIntersect16 / rtcIntersect1M and the occlusion forms, robust scene,
// each with both context flags; docs/oracle.md) on the same rays: 256x256 primary rays from the
// scene's default camera and one shadow ray per primary hit towards the default light.
//
// Per scene, the kd-tree, the Embree scene and the rays are built once, on first use, in a static
// cache (never timed). items_processed = rays, so Google Benchmark prints rays per second. The
// Embree benchmarks time Embree's calls only (the reset of the rays between passes is outside the
// manual timer). Every benchmark reports hit_rate (rays that hit, or are occluded); the kd
// benchmarks also report tests_per_ray (ray/triangle tests), leaves_per_ray, steps_per_ray (inner
// nodes) and vs_anchor = kd rays/s over the fastest Embree benchmark of the same scene and mode in
// this process (they are registered, and so run, just before; if a filter left them out, they are
// measured in the kd benchmark's set-up). Rates are rays per second of thread CPU time.
#include <benchmark/benchmark.h>

#include <time.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <exception>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/kdtree.hpp"
#include "simd/isa.hpp"
#include "oracle/embree_native_rays.hpp"
#include "bench_scenes.hpp"
#include "rays/workload.hpp"

namespace {

using beamtrace::Hit;
using beamtrace::KdTree;
using beamtrace::Packet16;
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
    Rays rays[2];                                                       // kPrimary, kShadow
    std::unique_ptr<beamtrace::oracle::EmbreeNativeRays> native[2][3];  // per mode and layout
    double anchor_rate[2] = {0, 0};            // rays/s of the fastest Embree benchmark run, per mode (0: none yet)
    bool anchor_in_setup[2] = {false, false};  // that rate was measured by the kd benchmark itself
};

Rays collect(const workload::RaySet& set, const KdTree& tree, Mode mode) {
    Rays r;
    r.packets = set.packets;  // Embree's layouts leave out the packets with no ray
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
    const std::optional<std::string> spec = beamtrace::bench::scene_spec(name, c->error);
    if (!spec) return c;
    try {
        workload::WorkloadConfig config;
        config.scene = *spec;
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

using beamtrace::oracle::EmbreeContextFlag;
using beamtrace::oracle::EmbreeLayout;
using beamtrace::oracle::EmbreeNativeRays;

constexpr EmbreeLayout kLayouts[] = {EmbreeLayout::single, EmbreeLayout::packet16, EmbreeLayout::stream};
constexpr EmbreeContextFlag kFlags[] = {EmbreeContextFlag::coherent, EmbreeContextFlag::incoherent};
const char* layout_name(EmbreeLayout l) {
    return l == EmbreeLayout::single ? "1" : l == EmbreeLayout::packet16 ? "16" : "_stream";
}

// The rays of a mode in one of Embree's layouts (made once per scene, mode and layout).
EmbreeNativeRays& native_rays(SceneCase& c, Mode mode, EmbreeLayout layout) {
    auto& slot = c.native[mode][int(layout)];
    if (!slot)
        slot = std::make_unique<EmbreeNativeRays>(*c.work->oracle, layout, c.rays[mode].packets, mode == kPrimary);
    return *slot;
}

// One pass of Embree's calls: thread CPU seconds of the calls alone (the reset before them is not
// counted), and the rays that hit (or are occluded).
double embree_pass(SceneCase& c, Mode mode, EmbreeLayout layout, EmbreeContextFlag flag, std::uint64_t& hits) {
    EmbreeNativeRays& native = native_rays(c, mode, layout);
    native.reset();
    const double start = thread_cpu_seconds();
    native.trace(flag, 0, native.units());
    const double seconds = thread_cpu_seconds() - start;
    if (mode == kPrimary) {
        std::vector<Hit> out;
        native.hits(out);
        for (const Hit& h : out) hits += h.hit();
    } else {
        std::vector<std::uint8_t> out;
        native.occluded(out);
        for (std::uint8_t o : out) hits += o;
    }
    return seconds;
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

void bm_embree(benchmark::State& state, const std::string& name, Mode mode, EmbreeLayout layout,
               EmbreeContextFlag flag) {
    SceneCase& c = scene_case(name);
    if (!usable(state, c)) return;
    std::uint64_t hits = 0;
    double cpu = 0;
    for (auto _ : state) {
        const double seconds = embree_pass(c, mode, layout, flag, hits);
        state.SetIterationTime(seconds);
        cpu += seconds;
    }
    const double rate = finish(state, c.rays[mode].single.size(), hits, cpu);
    if (rate > c.anchor_rate[mode]) c.anchor_rate[mode] = rate;
    c.anchor_in_setup[mode] = false;
    state.SetLabel(std::string("Embree robust, ") + beamtrace::oracle::to_string(flag) + ", " + c.description);
}

// The fastest Embree layout and flag for the scene and mode, measured here (0.1 s each).
double measure_anchor(SceneCase& c, Mode mode) {
    double best = 0;
    for (EmbreeLayout layout : kLayouts)
        for (EmbreeContextFlag flag : kFlags) {
            std::uint64_t passes = 0, hits = 0;
            double cpu = 0;
            while (cpu < 0.1) {
                cpu += embree_pass(c, mode, layout, flag, hits);
                ++passes;
            }
            best = std::max(best, double(passes) * double(c.rays[mode].single.size()) / cpu);
        }
    return best;
}

void bm_kd(benchmark::State& state, const std::string& name, Mode mode) {
    SceneCase& c = scene_case(name);
    if (!usable(state, c)) return;
    std::string label = std::string("kd-tree, ") + beamtrace::isa_name(beamtrace::best_isa()) + " kernels";
    if (c.anchor_rate[mode] <= 0) {
        // The Embree benchmarks did not run: measure the anchor here, untimed by Google Benchmark.
        c.anchor_rate[mode] = measure_anchor(c, mode);
        c.anchor_in_setup[mode] = true;
    }
    if (c.anchor_in_setup[mode]) label += " (anchor measured in set-up)";
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
    state.counters["vs_anchor"] = rate / c.anchor_rate[mode];
    state.SetLabel(label + ", " + c.description);
}

void register_benchmarks() {
    for (const char* scene : kScenes) {
        const std::string name = scene;
        for (Mode mode : {kPrimary, kShadow}) {
            const std::string prefix = std::string(mode_name(mode)) + "/" + name + "/";
            const char* query = mode == kPrimary ? "intersect" : "occluded";
            for (EmbreeLayout layout : kLayouts)
                for (EmbreeContextFlag flag : kFlags)
                    benchmark::RegisterBenchmark(
                        (prefix + "embree_" + query + layout_name(layout) + "/" + beamtrace::oracle::to_string(flag))
                            .c_str(),
                        [name, mode, layout, flag](benchmark::State& s) { bm_embree(s, name, mode, layout, flag); })
                        ->UseManualTime();
            benchmark::RegisterBenchmark((prefix + "kd_" + query).c_str(),
                                         [name, mode](benchmark::State& s) { bm_kd(s, name, mode); });
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
