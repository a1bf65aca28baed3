// The terms of the cost model of packet traversal and MLRTA (docs/mlrta.md, "Cost model"), each
// measured on realistic inputs: the 4x4 primary packets of a 1024x1024 image of the scene's default
// view (bunny, room), and what those packets meet in the tree.
//
//   <scene>/kd16_packet        a whole packet by the kd-tree's packet traversal from the root
//   <scene>/mlrta_packet       the image by MLRTA with the paper's packets (xp_packets 1, MTS 4):
//                              tiles, beams, entry points, per packet
//   <scene>/mlrta_2x2_packet   the same with 2x2 packets traced together (xp_packets 2, MTS 8)
//   <scene>/mlrta_4x4_packet   the same with 4x4 packets traced together (xp_packets 4, MTS 16: the
//                              defaults)
//   <scene>/mlrta_4x4_mts32_packet  the same with MTS 32 (tiles of at least 8x8 packets)
//   <scene>/packet_setup       a packet's set-up for interval traversal from the root: lanes
//                              (direction lengths, octants, validity), group ranges, the cut to the
//                              cell, the per-lane box rays, the one-origin frustum, the watertight
//                              packet
//   <scene>/beam_of_packet     Beam::add with the tree's set_ranges kernel, 64 packets a call, per
//                              packet (what MLRTA does for every packet of a tile's cells; the
//                              packets out of cache, as there)
//   <scene>/ep_search          an entry-point search of an initial tile's beam from the root
//   <scene>/triangle_test      one 16-ray watertight test (packet_x1), on the triangles the packet's
//                              rays hit (their copies in the leaf holding the hit, as traversal reads them)
//   <scene>/leaf_tests         the same test on every triangle of the leaf holding a lane's hit: the
//                              mix traversal meets (most of them miss every ray)
//   <scene>/lane_box           the per-lane box test of a leaf (the leaf holding a lane's hit)
//   <scene>/frustum_cull       the frustum culling of up to 16 triangles of that leaf (from the corner rows)
//
// Counters give each term's unit: per packet, per search (and per step of it), per test, per leaf.
// Time is the thread's CPU time; everything runs on one thread. The cost model puts them together:
// docs/mlrta.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/kdtree.hpp"
#include "beamtrace/mlrta.hpp"
#include "common/access.hpp"
#include "common/triangle_kernels.hpp"
#include "common/watertight_ray.hpp"
#include "kdtree/packet/lane_box_test.hpp"
#include "kdtree/packet/one_origin_frustum.hpp"
#include "kdtree/packet/packet_lanes.hpp"
#include "kdtree/packet/packet_traversal.hpp"
#include "mlrta/beam.hpp"
#include "mlrta/entry_point_search.hpp"
#include "mlrta/entry_point_trace.hpp"
#include "mlrta/mlrta_impl.hpp"
#include "bench_scenes.hpp"
#include "rays/workload.hpp"

namespace {

using namespace beamtrace;
namespace workload = beamtrace::workload;

constexpr int kImageSize = 1024;
const char* const kScenes[] = {"bunny", "room"};

// A leaf met by a packet: the packet and the leaf (node index and box).
struct LeafVisit {
    std::uint32_t packet;
    std::uint32_t node;
};

struct Case {
    std::string error;
    std::optional<workload::Workload> work;
    std::optional<KdTree> tree;
    std::optional<Mlrta> mlrta;
    std::vector<Packet16> packets;                               // with at least one active lane
    std::vector<std::pair<std::uint32_t, std::uint32_t>> tests;  // (packet, leaf triangle) pairs the packets' rays hit
    std::vector<LeafVisit> leaves;                               // (packet, leaf holding a lane's hit point)
};

// The leaf whose cell holds point p (descending by the splits).
std::uint32_t leaf_at(const KdTree::Impl& kd, Float3 p) {
    std::uint32_t i = 0;
    while (!kd.nodes[i].is_leaf()) {
        const KdNode& n = kd.nodes[i];
        i = p[n.axis()] <= n.split ? i + 1 : n.upper_child();
    }
    return i;
}

std::unique_ptr<Case> make_case(const std::string& name) {
    auto c = std::make_unique<Case>();
    const std::optional<std::string> spec = beamtrace::bench::scene_spec(name, c->error);
    if (!spec) return c;
    workload::WorkloadConfig config;
    config.scene = *spec;
    config.width = config.height = kImageSize;
    c->work.emplace(workload::make_workload(config));
    c->tree.emplace(KdTree::build(c->work->source.scene));
    c->tree->prepare_packet_queries();
    c->mlrta.emplace(*c->tree);
    const KdTree::Impl& kd = detail::Access::impl(*c->tree);
    const workload::RaySet& rays = c->work->rays;
    for (std::size_t p = 0; p < rays.packets.size(); ++p) {
        if ((rays.packets[p].active & 0xFFFFu) == 0) continue;
        const auto index = std::uint32_t(c->packets.size());
        c->packets.push_back(rays.packets[p]);
        std::vector<std::uint32_t> seen;
        for (int i = 0; i < 16; ++i) {
            const Hit& h = c->work->reference_hits[p * 16 + std::size_t(i)];
            if (!h.hit() || std::find(seen.begin(), seen.end(), h.triangle) != seen.end()) continue;
            seen.push_back(h.triangle);
            const Ray r = rays.packets[p].ray(i);
            const std::uint32_t leaf = leaf_at(kd, r.org + r.dir * h.t);
            c->leaves.push_back({index, leaf});
            // The triangle's copy in that leaf (a hit on the leaf's face may belong to its neighbour's
            // list only: then the pair is left out of the triangle test).
            const KdNode& node = kd.nodes[leaf];
            for (std::uint32_t j = 0; j < node.triangle_count(); ++j)
                if (kd.triangle_ids[node.offset() + j] == h.triangle) c->tests.emplace_back(index, node.offset() + j);
        }
    }
    return c;
}

Case& scene_case(const std::string& name) {
    static std::map<std::string, std::unique_ptr<Case>> cache;
    auto& slot = cache[name];
    if (!slot) {
        try {
            slot = make_case(name);
        } catch (const std::exception& e) {
            slot = std::make_unique<Case>();
            slot->error = e.what();
        }
    }
    return *slot;
}

// The lanes interval traversal takes together with the packet's first valid lane (one sign octant).
std::uint32_t first_octant(const kdtree::PacketLanes& lanes) {
    const std::uint32_t ok = lanes.valid & ~lanes.flat;
    if (ok == 0) return 0;
    const int i = __builtin_ctz(ok);
    int o = 0;
    for (int k = 0; k < 3; ++k)
        if ((lanes.negative[k] >> i) & 1u) o |= 1 << k;
    return kdtree::octant_lanes(lanes, ok, o);
}

bool usable(benchmark::State& state, const Case& c) {
    if (c.error.empty()) return true;
    state.SkipWithError(c.error.c_str());
    return false;
}

void per(benchmark::State& state, std::size_t items, const char* unit) {
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(items));
    state.SetLabel(std::string("items: ") + unit);
}

void bm_kd16_packet(benchmark::State& state, const std::string& name) {
    Case& c = scene_case(name);
    if (!usable(state, c)) return;
    const KdTree::Impl& kd = detail::Access::impl(*c.tree);
    const kdtree::PacketTraversalContext context{kd, kd.packet_tables(), true};
    const kdtree::TraversalStart root = kdtree::root_start(kd);
    PacketHits16 hits;
    for (auto _ : state)
        for (const Packet16& p : c.packets) {
            kdtree::trace_packet<false, false>(context, p, root, &hits, nullptr, nullptr);
            benchmark::DoNotOptimize(hits);
        }
    QueryCounters counters;
    for (const Packet16& p : c.packets) kdtree::trace_packet<false, true>(context, p, root, &hits, nullptr, &counters);
    const double n = double(c.packets.size());
    state.counters["steps_per_packet"] = double(counters.packet_steps) / n;
    state.counters["tests_per_packet"] = double(counters.triangle_tests) / n;
    state.counters["single_rays_per_packet"] = double(counters.single_rays) / n;
    per(state, c.packets.size(), "packets");
}

// MLRTA with `side` x `side` packets traced together (1: the paper's 4x4 packets) and tiles of at
// least `min_tile` pixels.
void bm_mlrta_packet_side(benchmark::State& state, const std::string& name, int side, int min_tile) {
    Case& c = scene_case(name);
    if (!usable(state, c)) return;
    MlrtaSettings settings = c.mlrta->settings();
    settings.experimental.xp_packets = side;
    settings.min_tile = min_tile;
    const Mlrta mlrta(*c.tree, settings);
    const workload::RaySet& rays = c.work->rays;
    const PacketGrid grid{rays.packets.data(), rays.packets_x, rays.packets_y};
    std::vector<PacketHits16> hits(rays.packets.size());
    for (auto _ : state) {
        mlrta.intersect(grid, hits);
        benchmark::DoNotOptimize(hits.data());
    }
    QueryCounters counters;
    mlrta.intersect(grid, hits, QueryOptions{1, &counters});
    const double n = double(rays.packets.size());
    state.counters["ep_steps_per_packet"] = double(counters.mlrta.ep_steps) / n;
    state.counters["xp_steps_per_packet"] = double(counters.packet_steps) / n;
    state.counters["tests_per_packet"] = double(counters.triangle_tests) / n;
    state.counters["tiles"] = double(counters.mlrta.tiles);
    per(state, rays.packets.size(), "packets of the grid");
}
void bm_mlrta_packet(benchmark::State& state, const std::string& name) {
    bm_mlrta_packet_side(state, name, 1, 4);  // the paper's 4x4 packets and minimum tile
}
void bm_mlrta_2x2_packet(benchmark::State& state, const std::string& name) { bm_mlrta_packet_side(state, name, 2, 8); }
void bm_mlrta_4x4_packet(benchmark::State& state, const std::string& name) { bm_mlrta_packet_side(state, name, 4, 16); }
void bm_mlrta_4x4_mts32_packet(benchmark::State& state, const std::string& name) {
    bm_mlrta_packet_side(state, name, 4, 32);
}

// A packet's set-up as traversal does it from the root (lanes, group ranges, then the cut to the
// cell, the farthest distance, the frustum, the watertight packet and the box rays), with the
// kernels traversal calls (the tree's instruction set; BEAMTRACE_ISA chooses another).
void bm_packet_setup(benchmark::State& state, const std::string& name) {
    Case& c = scene_case(name);
    if (!usable(state, c)) return;
    const KdTree::Impl& kd = detail::Access::impl(*c.tree);
    const float pad = kd.packet_tables().pad;
    const kdtree::PacketSetupKernels& setup = kd.packet_tables().kernels->setup;
    WatertightPacket16 wp;
    kdtree::LaneBoxRays box_rays;
    kdtree::OneOriginFrustum f;
    kdtree::PacketLanes lanes;
    for (auto _ : state)
        for (const Packet16& p : c.packets) {
            setup.lanes(p, lanes);
            const std::uint32_t mask = first_octant(lanes);
            if (mask == 0) continue;
            benchmark::DoNotOptimize(setup.group_ranges(p, lanes, mask));
            const kdtree::CellEntry e = setup.enter_cell(p, mask, lanes.speed, kd.bounds, pad);
            const float far = setup.farthest_distance(p.tfar, lanes.speed, e.lanes);
            f = setup.frustum(p, e.lanes);
            setup.watertight(p, wp);
            setup.box_rays(p, pad, box_rays);
            benchmark::DoNotOptimize(e);
            benchmark::DoNotOptimize(far);
            benchmark::DoNotOptimize(f);
            benchmark::DoNotOptimize(wp);
            benchmark::DoNotOptimize(box_rays);
        }
    per(state, c.packets.size(), "packets");
}

void bm_beam_of_packet(benchmark::State& state, const std::string& name) {
    Case& c = scene_case(name);
    if (!usable(state, c)) return;
    // The kernel the engine uses (the tree's instruction set), not the lane-by-lane reference, over
    // 64 packets a call, as the engine makes the beams of its cells (8 x 8 packets at the default
    // minimum tile of 32 pixels): the ranges are reduced once a call.
    const kdtree::PacketSetRangesKernel ranges = detail::Access::impl(*c.tree).packet_tables().kernels->setup.set_ranges;
    std::vector<const Packet16*> all;
    for (const Packet16& p : c.packets) all.push_back(&p);
    constexpr std::size_t kCell = 64;
    for (auto _ : state)
        for (std::size_t i = 0; i < all.size(); i += kCell) {
            mlrta::Beam b;
            b.add(std::span<const Packet16* const>(all.data() + i, std::min(kCell, all.size() - i)), ranges);
            benchmark::DoNotOptimize(b);
        }
    per(state, c.packets.size(), "packets");
}

void bm_ep_search(benchmark::State& state, const std::string& name) {
    Case& c = scene_case(name);
    if (!usable(state, c)) return;
    const Mlrta::Impl& m = detail::Access::impl(*c.mlrta);
    const workload::RaySet& rays = c.work->rays;
    // The beams of the initial tiles (ITS 128 px: 32 x 32 packets).
    const int side = m.settings.initial_tile / 4;
    std::vector<mlrta::Beam> beams;
    for (int ty = 0; ty < rays.packets_y; ty += side)
        for (int tx = 0; tx < rays.packets_x; tx += side) {
            mlrta::Beam beam;
            beam.set_scene_scale(m.kd().bounds);
            for (int y = ty; y < std::min(ty + side, rays.packets_y); ++y)
                for (int x = tx; x < std::min(tx + side, rays.packets_x); ++x) {
                    mlrta::Beam b;
                    b.pad = beam.pad;
                    b.add(rays.packets[std::size_t(y) * std::size_t(rays.packets_x) + std::size_t(x)]);
                    beam.merge(b);
                }
            if (!beam.empty && beam.coherent) beams.push_back(beam);
        }
    const mlrta::EntryPoint root = mlrta::root_entry(m);
    std::uint64_t steps = 0;
    for (auto _ : state) {
        steps = 0;
        for (const mlrta::Beam& b : beams) benchmark::DoNotOptimize(mlrta::entry_point_search(m, b, root, steps));
    }
    state.counters["steps_per_search"] = beams.empty() ? 0.0 : double(steps) / double(beams.size());
    state.counters["ns_per_step"] =
        benchmark::Counter(double(steps), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
    per(state, beams.size(), "searches of initial tiles");
}

// A packet against a run of leaf triangles (their copies as traversal reads them).
struct TestRun {
    std::uint32_t packet;
    std::uint32_t first, count;  // into the tree's leaf triangles
};

// 16-ray tests with their inputs in cache, as in traversal, where a packet's set-up stays in L1 for
// all its tests: runs in blocks of 256, each block's packets set up side by side first (untimed),
// then every run tested a few times. Counts the share of tests that hit some ray.
void time_packet_tests(benchmark::State& state, const Case& c, const std::vector<TestRun>& runs, const char* label) {
    const KdTree::Impl& kd = detail::Access::impl(*c.tree);
    const TriangleKernels& kernels = *kd.kernels;
    constexpr std::size_t kBlock = 256;
    constexpr int kRounds = 4;
    std::vector<WatertightPacket16> set_up(kBlock);
    LaneHits lanes;
    std::size_t tests = 0, hitting = 0;
    for (auto _ : state) {
        for (std::size_t b = 0; b < runs.size(); b += kBlock) {
            const std::size_t n = std::min(kBlock, runs.size() - b);
            state.PauseTiming();
            for (std::size_t i = 0; i < n; ++i) set_up[i] = make_watertight_packet(c.packets[runs[b + i].packet]);
            state.ResumeTiming();
            for (int round = 0; round < kRounds; ++round)
                for (std::size_t i = 0; i < n; ++i)
                    for (std::uint32_t j = 0; j < runs[b + i].count; ++j) {
                        kernels.packet_x1(set_up[i], kd.leaf_triangles[runs[b + i].first + j], lanes);
                        hitting += lanes.mask != 0;
                        ++tests;
                    }
        }
    }
    state.SetItemsProcessed(std::int64_t(tests));
    state.counters["hit_rate"] = tests ? double(hitting) / double(tests) : 0.0;
    state.SetLabel(label);
}

void bm_triangle_test(benchmark::State& state, const std::string& name) {
    Case& c = scene_case(name);
    if (!usable(state, c)) return;
    std::vector<TestRun> runs;
    for (const auto& [packet, triangle] : c.tests) runs.push_back({packet, triangle, 1});
    time_packet_tests(state, c, runs, "items: 16-ray triangle tests (inputs in cache)");
}

// Every triangle of the leaf holding a lane's hit against the packet: the mix traversal meets
// (hits, triangles between the packet's rays, triangles behind its hits), inputs in cache.
void bm_leaf_tests(benchmark::State& state, const std::string& name) {
    Case& c = scene_case(name);
    if (!usable(state, c)) return;
    const KdTree::Impl& kd = detail::Access::impl(*c.tree);
    std::vector<TestRun> runs;
    for (const LeafVisit& v : c.leaves)
        runs.push_back({v.packet, kd.nodes[v.node].offset(), kd.nodes[v.node].triangle_count()});
    time_packet_tests(state, c, runs, "items: 16-ray triangle tests of whole leaves (inputs in cache)");
}

void bm_lane_box(benchmark::State& state, const std::string& name) {
    Case& c = scene_case(name);
    if (!usable(state, c)) return;
    const KdTree::Impl& kd = detail::Access::impl(*c.tree);
    const kdtree::PacketTables& tables = kd.packet_tables();
    std::vector<kdtree::LaneBoxRays> set_up;
    for (const Packet16& p : c.packets) set_up.push_back(kdtree::make_lane_box_rays(p, 1e-6f));
    std::uint32_t met = 0;
    for (auto _ : state)
        for (const LeafVisit& v : c.leaves) {
            const Packet16& p = c.packets[v.packet];
            met += tables.kernels->lane_box(set_up[v.packet], p.tfar, p.active, tables.geometry_boxes[v.node]);
        }
    benchmark::DoNotOptimize(met);
    per(state, c.leaves.size(), "leaves");
}

void bm_frustum_cull(benchmark::State& state, const std::string& name) {
    Case& c = scene_case(name);
    if (!usable(state, c)) return;
    const KdTree::Impl& kd = detail::Access::impl(*c.tree);
    const kdtree::PacketTables& tables = kd.packet_tables();
    std::vector<kdtree::OneOriginFrustum> frusta;
    for (const Packet16& p : c.packets) {
        const kdtree::PacketLanes lanes = kdtree::packet_lanes(p);
        frusta.push_back(kdtree::make_one_origin_frustum(p, first_octant(lanes)));
    }
    std::uint32_t culled = 0;
    std::uint64_t triangles = 0;
    for (auto _ : state)
        for (const LeafVisit& v : c.leaves) {
            const KdNode& leaf = kd.nodes[v.node];
            const int n = int(std::min<std::uint32_t>(16, leaf.triangle_count()));
            culled += tables.kernels->frustum_cull(frusta[v.packet], tables.rows(), leaf.offset(), n);
            triangles += std::uint64_t(n);
        }
    benchmark::DoNotOptimize(culled);
    state.counters["triangles_per_call"] =
        state.iterations() ? double(triangles) / double(state.iterations()) / double(c.leaves.size()) : 0.0;
    per(state, c.leaves.size(), "leaves (up to 16 triangles)");
}

void register_all() {
    for (const char* scene : kScenes) {
        const std::string s = scene;
        const auto add = [&](const char* what, void (*f)(benchmark::State&, const std::string&)) {
            benchmark::RegisterBenchmark((s + "/" + what).c_str(), [s, f](benchmark::State& st) {
                f(st, s);
            })->Unit(benchmark::kMillisecond);
        };
        add("kd16_packet", bm_kd16_packet);
        add("mlrta_packet", bm_mlrta_packet);
        add("mlrta_2x2_packet", bm_mlrta_2x2_packet);
        add("mlrta_4x4_packet", bm_mlrta_4x4_packet);
        add("mlrta_4x4_mts32_packet", bm_mlrta_4x4_mts32_packet);
        add("packet_setup", bm_packet_setup);
        add("beam_of_packet", bm_beam_of_packet);
        add("ep_search", bm_ep_search);
        add("triangle_test", bm_triangle_test);
        add("leaf_tests", bm_leaf_tests);
        add("lane_box", bm_lane_box);
        add("frustum_cull", bm_frustum_cull);
    }
}

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    register_all();
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
