// The terms of the stream tracer's cost model (docs/streams.md, "Cost model"), each measured alone
// on a realistic stream: the ambient-occlusion rays (16 per pixel) of a 512x512 image of `room`
// (and of bunny), in one fixed random order (a wavefront integrator's), traced as occlusion rays.
// BEAMTRACE_STREAM_BENCH_SIZE=1024 measures the 1024x1024 image instead (16.7 million rays).
//
//   <scene>/shared_points   sampling the stream for shared points (per call)
//   <scene>/keys            one key per ray, the widest instruction set's kernel (per ray)
//   <scene>/keys_scalar     the same by the scalar reference (per ray)
//   <scene>/radix_sort      the sort of the keys and the origins' hashes (per ray)
//   <scene>/gather          the rays copied into sorted order (per ray)
//   <scene>/sort_rays       the sort and the gather in one (stream/ray_sort.hpp; per ray)
//   <scene>/cut_groups      the sorted keys cut into groups (per ray)
//   <scene>/origin_group    one group of rays with one origin by the masked group traversal (per group)
//   <scene>/single_sorted   the same rays one by one (single-ray traversal) in sorted order (per ray)
//   <scene>/single_shuffled the same rays one by one in the shuffled order (per ray)
//   <scene>/bvh_sorted      the same rays one by one through the wide BVH (bvh/wide_bvh.hpp), sorted order (per ray)
//   <scene>/bvh_shuffled    the same in the shuffled order (per ray)
//   <scene>/stream          the whole StreamTracer::occluded call (per ray)
//   <scene>/diffuse_single  diffuse bounces (one closest-hit ray per primary hit) one by one, by origin cell (per ray)
//   <scene>/diffuse_bvh     the same through the wide BVH, by origin cell (per ray)
//   <scene>/diffuse_bvh_shuffled  the same in the shuffled order (per ray)
//   <scene>/shadow_bvh_packets    shadow rays to the default light in their 4x4 packets, input order: the
//                                 wide BVH's packet walk (bvh::occluded_packet; per ray)
//   <scene>/shadow_bvh_rays       the same rays one by one through the wide BVH (per ray)
//   <scene>/shadow_mlrta          the same packets by the mlrta engine's tiles of beams (the paper's
//                                 method: MlrtaExperimental::shadow_bvh off; per ray)
//   <scene>/embree_ao_shuffled    Embree's rtcOccluded1 (incoherent context) on bvh_shuffled's rays: the
//                                 anchor's single-ray kernel on the same inputs, per ray
//   <scene>/embree_diffuse_shuffled  Embree's rtcIntersect1 on diffuse_bvh_shuffled's rays (per ray)
//   <scene>/embree_diffuse_hot       the same on diffuse_bvh_hot's 1,024 rays (per ray)
//   <scene>/diffuse_bvh_hot       diffuse_bvh on the first 1,024 rays only (the nodes they meet stay in
//                                 cache: the arithmetic's and the branches' share; per ray)
//   <scene>/diffuse_bvh_leafN     diffuse_bvh with leaves of at most N triangles (12 above; per ray)
//   <scene>/diffuse_group   the same, 16 consecutive ones a group, masked group traversal (per ray)
//   <scene>/diffuse_stream  the whole StreamTracer::intersect call on them, shuffled, defaults (per ray)
//   <scene>/diffuse_stream_kd       the same without the wide BVH: loose groups through the kd-tree (per ray)
//   <scene>/diffuse_stream_singles  the same with loose rays one by one through the kd-tree (per ray)
//
// Time is the thread's CPU time; everything runs on one thread.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/kdtree.hpp"
#include "beamtrace/mlrta.hpp"
#include "beamtrace/stream.hpp"
#include "common/access.hpp"
#include "bvh/wide_bvh.hpp"
#include "bvh/wide_bvh_packet.hpp"
#include "kdtree/ray_traversal.hpp"
#include "stream/group_traversal.hpp"
#include "stream/radix_sort.hpp"
#include "stream/ray_groups.hpp"
#include "stream/ray_keys.hpp"
#include "stream/ray_sort.hpp"
#include "bench_scenes.hpp"
#include "oracle/embree_oracle.hpp"
#include "rays/workload.hpp"

namespace {

using namespace beamtrace;
namespace workload = beamtrace::workload;

int image_size() {
    const char* size = std::getenv("BEAMTRACE_STREAM_BENCH_SIZE");
    return size ? std::max(16, std::atoi(size)) : 512;
}
const char* const kScenes[] = {"room", "bunny"};

struct StreamCase {
    std::string error;
    std::optional<KdTree> tree;
    std::vector<Ray> rays;  // shuffled
    stream::SharedPoints shared;
    std::vector<std::uint32_t> keys, hashes, order, sorted_keys;
    std::vector<Ray> sorted;  // the rays in the sort's order (for the terms that trace them)
    std::vector<stream::RayGroup> groups;
    stream::SortBuffers sort_buffers;
    stream::RaySortBuffers ray_sort_buffers;
};

// The rays of `mode` on the scene `name` in one fixed random order (a wavefront integrator's), and the
// scene's kd-tree; nothing when the scene is missing (then error says why).
std::vector<Ray> shuffled_workload(const std::string& name, workload::Mode mode, std::optional<KdTree>& tree,
                                   std::string& error) {
    std::vector<Ray> rays;
    const std::optional<std::string> spec = bench::scene_spec(name, error);
    if (!spec) return rays;
    workload::WorkloadConfig config;
    config.scene = *spec;
    config.mode = mode;
    config.width = config.height = image_size();
    const workload::Workload w = workload::make_workload(config);
    for (std::size_t s = 0; s < w.rays.slots(); ++s)
        if (w.rays.active(s)) rays.push_back(w.rays.ray(s));
    std::mt19937 random(7);
    std::shuffle(rays.begin(), rays.end(), random);
    tree.emplace(KdTree::build(w.source.scene));
    return rays;
}

// A case of the scene `name`, made by fill on first use and kept for the benchmarks after.
template <class Case, class Fill>
Case& cached_case(const std::string& name, const Fill& fill) {
    static std::map<std::string, std::unique_ptr<Case>> cache;
    auto& slot = cache[name];
    if (!slot) {
        slot = std::make_unique<Case>();
        fill(*slot);
    }
    return *slot;
}

void fill_stream_case(const std::string& name, StreamCase& c) {
    c.rays = shuffled_workload(name, workload::Mode::ao, c.tree, c.error);
    if (!c.tree) return;
    const KdTree::Impl& kd = detail::Access::impl(*c.tree);
    const std::size_t n = c.rays.size();
    c.shared = stream::find_shared_points(c.rays, kd.bounds, 4096, 0.01f, StreamSettings::kMaxSharedPoints);
    c.keys.resize(n);
    c.order.resize(n);
    c.sorted_keys.resize(n);
    c.sorted.resize(n);
    stream::make_keys(c.rays, kd.bounds, c.shared, c.keys);
    c.hashes.resize(n);
    for (std::size_t i = 0; i < n; ++i) c.hashes[i] = stream::origin_hash(c.rays[i]);
    stream::sort_by_key(c.keys, c.hashes, c.order, c.sorted_keys, 1, c.sort_buffers);
    stream::gather_in_order(c.rays, c.order, 0, n, c.sorted);
    stream::cut_groups(c.sorted_keys, 4, c.groups);
}

StreamCase& stream_case(const std::string& name) {
    return cached_case<StreamCase>(name, [&](StreamCase& c) { fill_stream_case(name, c); });
}

bool usable(benchmark::State& state, const StreamCase& c) {
    if (c.error.empty()) return true;
    state.SkipWithError(c.error.c_str());
    return false;
}

void per_ray(benchmark::State& state, std::size_t rays) {
    state.SetItemsProcessed(std::int64_t(state.iterations() * rays));
    // Seconds per ray (Google Benchmark prints it with its unit prefix: 21n is 21 ns).
    state.counters["per_ray"] = benchmark::Counter(double(state.iterations()) * double(rays),
                                                   benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void bm_shared_points(benchmark::State& state, const std::string& name) {
    StreamCase& c = stream_case(name);
    if (!usable(state, c)) return;
    const Box box = detail::Access::impl(*c.tree).bounds;
    for (auto _ : state) benchmark::DoNotOptimize(stream::find_shared_points(c.rays, box, 4096, 0.01f, 16));
}

void bm_keys(benchmark::State& state, const std::string& name, Isa isa) {
    StreamCase& c = stream_case(name);
    if (!usable(state, c)) return;
    const Box box = detail::Access::impl(*c.tree).bounds;
    for (auto _ : state) {
        stream::make_keys(c.rays, box, c.shared, c.keys, isa);
        benchmark::DoNotOptimize(c.keys.data());
    }
    per_ray(state, c.rays.size());
}

void bm_radix_sort(benchmark::State& state, const std::string& name) {
    StreamCase& c = stream_case(name);
    if (!usable(state, c)) return;
    for (auto _ : state) {
        stream::sort_by_key(c.keys, c.hashes, c.order, c.sorted_keys, 1, c.sort_buffers);
        benchmark::DoNotOptimize(c.order.data());
    }
    per_ray(state, c.rays.size());
}

void bm_gather(benchmark::State& state, const std::string& name) {
    StreamCase& c = stream_case(name);
    if (!usable(state, c)) return;
    for (auto _ : state) {
        stream::gather_in_order(c.rays, c.order, 0, c.rays.size(), c.sorted);
        benchmark::DoNotOptimize(c.sorted.data());
    }
    per_ray(state, c.rays.size());
}

void bm_sort_rays(benchmark::State& state, const std::string& name) {
    StreamCase& c = stream_case(name);
    if (!usable(state, c)) return;
    for (auto _ : state) {
        stream::sort_rays(c.rays, c.keys, c.hashes, c.order, c.sorted_keys, c.sorted, 1, c.ray_sort_buffers);
        benchmark::DoNotOptimize(c.sorted.data());
    }
    per_ray(state, c.rays.size());
}

void bm_cut_groups(benchmark::State& state, const std::string& name) {
    StreamCase& c = stream_case(name);
    if (!usable(state, c)) return;
    for (auto _ : state) {
        stream::cut_groups(c.sorted_keys, 4, c.groups);
        benchmark::DoNotOptimize(c.groups.data());
    }
    per_ray(state, c.rays.size());
    state.counters["groups"] = double(c.groups.size());
}

void bm_origin_group(benchmark::State& state, const std::string& name) {
    StreamCase& c = stream_case(name);
    if (!usable(state, c)) return;
    const KdTree::Impl& kd = detail::Access::impl(*c.tree);
    // The runs of one origin (the stream tracer's origin groups: at least 4 rays, at most 16).
    std::vector<Packet16> packets;
    for (std::size_t k = 0; k < c.sorted.size();) {
        std::size_t e = k + 1;
        while (e < c.sorted.size() && e - k < 16 && c.sorted_keys[e] == c.sorted_keys[k] &&
               c.sorted[e].org.x == c.sorted[k].org.x && c.sorted[e].org.y == c.sorted[k].org.y &&
               c.sorted[e].org.z == c.sorted[k].org.z)
            ++e;
        if (e - k >= 4 && (c.sorted_keys[k] & stream::kPencilBit) == 0) {
            Packet16 p;
            for (std::size_t i = 0; i < 16; ++i)
                p.set_ray(int(i), k + i < e ? c.sorted[k + i] : Ray{{0, 0, 0}, 0, {0, 0, 1}, 0});
            p.active = e - k >= 16 ? 0xFFFFu : (1u << (e - k)) - 1u;
            packets.push_back(p);
        }
        k = e;
    }
    if (packets.empty()) {
        state.SkipWithError("no origin groups");
        return;
    }
    std::size_t next = 0;
    std::uint32_t bits = 0;
    PacketHits16 hits;
    for (auto _ : state) {
        stream::trace_group<true, false>(kd, packets[next], &hits, &bits, nullptr);
        benchmark::DoNotOptimize(bits);
        next = next + 1 == packets.size() ? 0 : next + 1;
    }
    QueryCounters counters;
    for (const Packet16& p : packets) stream::trace_group<true, true>(kd, p, &hits, &bits, &counters);
    const double g = double(packets.size());
    state.counters["steps_per_group"] = double(counters.stream.group_steps) / g;
    state.counters["leaves_per_group"] = double(counters.stream.group_leaves) / g;
    state.counters["unreached_planes_per_group"] = double(counters.stream.group_unreached_planes) / g;
    state.counters["tests_per_group"] = double(counters.triangle_tests) / g;
}

void bm_single(benchmark::State& state, const std::string& name, bool sorted) {
    StreamCase& c = stream_case(name);
    if (!usable(state, c)) return;
    const KdTree::Impl& kd = detail::Access::impl(*c.tree);
    const std::vector<Ray>& rays = sorted ? c.sorted : c.rays;
    std::size_t next = 0, hits = 0;
    for (auto _ : state) {
        hits += kdtree::occluded_one(kd, rays[next]);
        next = next + 1 == rays.size() ? 0 : next + 1;
    }
    benchmark::DoNotOptimize(hits);
    per_ray(state, 1);
}

// The scene's wide BVH, built once per scene (its build time is reported once, as a counter).
const bvh::WideBvh& wide_bvh(const KdTree& tree, int leaf) {
    static std::map<std::pair<const void*, int>, std::shared_ptr<const bvh::WideBvh>> cache;
    auto& slot = cache[{&detail::Access::impl(tree), leaf}];
    bvh::WideBvhSettings s;
    s.max_leaf_triangles = leaf;
    if (!slot) slot = bvh::WideBvh::build(tree.scene(), s);
    return *slot;
}

// Rays one by one through the wide BVH (occlusion or closest hit), with the per-ray counts of a
// counted pass.
void bvh_rays(benchmark::State& state, const KdTree& tree, const std::vector<Ray>& rays, bool occlusion,
              int leaf = bvh::WideBvhSettings{}.max_leaf_triangles) {
    const bvh::WideBvh& b = wide_bvh(tree, leaf);
    const bvh::WideBvhKernels& k = bvh::wide_bvh_kernels();
    std::size_t next = 0;
    float sum = 0;
    for (auto _ : state) {
        sum += (occlusion ? k.occluded : k.intersect)(b, rays[next]).t;
        next = next + 1 == rays.size() ? 0 : next + 1;
    }
    benchmark::DoNotOptimize(sum);
    per_ray(state, 1);
    QueryCounters counters;
    for (const Ray& r : rays) (occlusion ? k.occluded_counted : k.intersect_counted)(b, r, &counters);
    const double n = double(rays.size());
    state.counters["nodes_per_ray"] = double(counters.inner_steps) / n;
    state.counters["leaves_per_ray"] = double(counters.leaves) / n;
    state.counters["tests_per_ray"] = double(counters.triangle_tests) / n;
    state.counters["build_s"] = b.stats.build_seconds;
    state.counters["bvh_MB"] = double(b.stats.memory_bytes) / 1e6;
    std::size_t le16 = 0, kids = 0;
    for (std::size_t i = 0; i < b.stats.inner_nodes; ++i) {
        int k = 0;
        while (k < bvh::kWidth && b.nodes[i].child[k] != bvh::kEmpty) ++k;
        kids += std::size_t(k);
        le16 += k <= 16;
    }
    state.counters["nodes_le16"] = double(le16) / double(b.stats.inner_nodes);
    state.counters["children"] = double(kids) / double(b.stats.inner_nodes);
}

// Embree's single-ray calls on the same rays (rays prebuilt in its layout, incoherent context): the
// anchor's kernel term by term against bvh_rays. The scene is robust, as the bench's anchor engines.
void embree_rays(benchmark::State& state, const KdTree& tree, const std::vector<Ray>& rays, bool occlusion) {
    static std::map<const KdTree*, std::unique_ptr<oracle::EmbreeOracle>> cache;
    auto& embree = cache[&tree];
    if (!embree) embree = std::make_unique<oracle::EmbreeOracle>(tree.scene());
    RTCScene scene = embree->native_scene();
    std::vector<RTCRayHit> native(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& r = rays[i];
        RTCRay& n = native[i].ray;
        n = RTCRay{};
        n.org_x = r.org.x, n.org_y = r.org.y, n.org_z = r.org.z, n.tnear = r.tnear;
        n.dir_x = r.dir.x, n.dir_y = r.dir.y, n.dir_z = r.dir.z, n.tfar = r.tfar;
        n.mask = ~0u;
        n.id = unsigned(i);
        native[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    std::size_t next = 0;
    float sum = 0;
    for (auto _ : state) {
        RTCRayHit q = native[next];
        if (occlusion) {
            rtcOccluded1(scene, &context, &q.ray);
        } else {
            rtcIntersect1(scene, &context, &q);
        }
        sum += q.ray.tfar;
        next = next + 1 == rays.size() ? 0 : next + 1;
    }
    benchmark::DoNotOptimize(sum);
    per_ray(state, 1);
}

// Shadow rays to the default light in their 4x4 pixel packets (input order, coherent): the packet
// walk of the wide BVH (bvh::occluded_packet), the same packets' rays one by one through it, and the
// mlrta engine's packets, per ray.
struct ShadowCase {
    std::string error;
    std::optional<KdTree> tree;
    std::vector<Packet16> packets;
    int columns = 0, rows = 0;  // the packets' image
    std::size_t rays = 0;
};

void fill_shadow_case(const std::string& name, ShadowCase& c) {
    const std::optional<std::string> spec = bench::scene_spec(name, c.error);
    if (!spec) return;
    workload::WorkloadConfig config;
    config.scene = *spec;
    config.mode = workload::Mode::shadow;
    config.width = config.height = image_size();
    const workload::Workload w = workload::make_workload(config);
    c.packets = w.rays.packets;
    c.columns = w.rays.packets_x;
    c.rows = w.rays.packets_y;
    c.rays = w.rays.ray_count;
    c.tree.emplace(KdTree::build(w.source.scene));
}

ShadowCase& shadow_case(const std::string& name) {
    return cached_case<ShadowCase>(name, [&](ShadowCase& c) { fill_shadow_case(name, c); });
}

void bm_shadow_packets(benchmark::State& state, const std::string& name, bool as_packets) {
    ShadowCase& c = shadow_case(name);
    if (!c.error.empty()) return state.SkipWithError(c.error.c_str());
    const bvh::WideBvh& b = wide_bvh(*c.tree, bvh::WideBvhSettings{}.max_leaf_triangles);
    const bvh::WideBvhKernels& k = bvh::wide_bvh_kernels();
    // One packet's answers: its walk, or its rays one by one (counted when counters is set).
    const auto occluded = [&](const Packet16& p, QueryCounters* counters) {
        if (as_packets) return bvh::occluded_packet(b, p, k.isa, counters);
        std::uint32_t bits = 0;
        for (std::uint32_t m = p.active & 0xFFFFu; m != 0; m &= m - 1) {
            const Ray ray = p.ray(__builtin_ctz(m));
            if ((counters ? k.occluded_counted(b, ray, counters) : k.occluded(b, ray)).hit())
                bits |= 1u << __builtin_ctz(m);
        }
        return bits;
    };
    std::vector<std::uint32_t> out(c.packets.size());
    for (auto _ : state) {
        for (std::size_t i = 0; i < c.packets.size(); ++i) out[i] = occluded(c.packets[i], nullptr);
        benchmark::DoNotOptimize(out.data());
    }
    per_ray(state, c.rays);
    std::size_t occluded_rays = 0;
    for (const std::uint32_t o : out) occluded_rays += std::size_t(__builtin_popcount(o));
    state.counters["occluded"] = double(occluded_rays) / double(c.rays);
    QueryCounters counters;
    for (const Packet16& p : c.packets) occluded(p, &counters);
    const double n = double(c.packets.size());
    state.counters["nodes_per_packet"] = double(counters.inner_steps + counters.packet_steps) / n;
    state.counters["leaves_per_packet"] = double(counters.leaves) / n;
    state.counters["tests_per_packet"] = double(counters.triangle_tests) / n;
}

void bm_shadow_mlrta(benchmark::State& state, const std::string& name) {
    ShadowCase& c = shadow_case(name);
    if (!c.error.empty()) return state.SkipWithError(c.error.c_str());
    MlrtaSettings settings;
    settings.experimental.shadow_bvh = false;  // the paper's tiles of beams
    const Mlrta engine(*c.tree, settings);
    const PacketGrid grid{c.packets.data(), c.columns, c.rows};
    std::vector<std::uint32_t> out(c.packets.size());
    for (auto _ : state) {
        engine.occluded(grid, out);
        benchmark::DoNotOptimize(out.data());
    }
    per_ray(state, c.rays);
}

void bm_bvh(benchmark::State& state, const std::string& name, bool sorted) {
    StreamCase& c = stream_case(name);
    if (!usable(state, c)) return;
    bvh_rays(state, *c.tree, sorted ? c.sorted : c.rays, true);
}

void bm_stream(benchmark::State& state, const std::string& name) {
    StreamCase& c = stream_case(name);
    if (!usable(state, c)) return;
    const StreamTracer tracer(*c.tree);
    std::vector<std::uint8_t> occluded(c.rays.size());
    for (auto _ : state) {
        tracer.occluded(c.rays, occluded);
        benchmark::DoNotOptimize(occluded.data());
    }
    per_ray(state, c.rays.size());
}

// Diffuse bounces (one ray per primary hit, closest hit, shuffled): every ray loose (no shared origin
// or point). The rays in the sort's order (by origin cell) traced one by one, or as groups of 16
// consecutive ones by the masked group traversal; and whole StreamTracer calls with loose groups
// (windows of sorted neighbours put in order of direction) and with loose rays one by one.
struct DiffuseCase {
    std::string error;
    std::optional<KdTree> tree;
    std::vector<Ray> shuffled, by_origin;
};

void fill_diffuse_case(const std::string& name, DiffuseCase& c) {
    c.shuffled = shuffled_workload(name, workload::Mode::diffuse, c.tree, c.error);
    if (!c.tree) return;
    const Box box = detail::Access::impl(*c.tree).bounds;
    c.by_origin = c.shuffled;
    std::stable_sort(c.by_origin.begin(), c.by_origin.end(), [&](const Ray& a, const Ray& b) {
        return stream::morton_cell(a.org, box) < stream::morton_cell(b.org, box);
    });
}

DiffuseCase& diffuse_case(const std::string& name) {
    return cached_case<DiffuseCase>(name, [&](DiffuseCase& c) { fill_diffuse_case(name, c); });
}

void bm_diffuse_single(benchmark::State& state, const std::string& name) {
    DiffuseCase& c = diffuse_case(name);
    if (!c.error.empty()) return state.SkipWithError(c.error.c_str());
    const KdTree::Impl& kd = detail::Access::impl(*c.tree);
    std::size_t next = 0;
    float sum = 0;
    for (auto _ : state) {
        sum += kdtree::intersect_one(kd, c.by_origin[next]).t;
        next = next + 1 == c.by_origin.size() ? 0 : next + 1;
    }
    benchmark::DoNotOptimize(sum);
    per_ray(state, 1);
}

void bm_diffuse_bvh(benchmark::State& state, const std::string& name, bool shuffled, int leaf) {
    DiffuseCase& c = diffuse_case(name);
    if (!c.error.empty()) return state.SkipWithError(c.error.c_str());
    bvh_rays(state, *c.tree, shuffled ? c.shuffled : c.by_origin, false, leaf);
}

void bm_diffuse_group(benchmark::State& state, const std::string& name) {
    DiffuseCase& c = diffuse_case(name);
    if (!c.error.empty()) return state.SkipWithError(c.error.c_str());
    const KdTree::Impl& kd = detail::Access::impl(*c.tree);
    std::vector<Packet16> packets;
    for (std::size_t k = 0; k + 16 <= c.by_origin.size(); k += 16) {
        Packet16 p;
        for (int i = 0; i < 16; ++i) p.set_ray(i, c.by_origin[k + std::size_t(i)]);
        p.active = 0xFFFFu;
        packets.push_back(p);
    }
    std::size_t next = 0;
    PacketHits16 hits;
    for (auto _ : state) {
        stream::trace_group<false, false>(kd, packets[next], &hits, nullptr, nullptr);
        benchmark::DoNotOptimize(hits);
        next = next + 1 == packets.size() ? 0 : next + 1;
    }
    per_ray(state, 16);
    QueryCounters counters;
    for (const Packet16& p : packets) stream::trace_group<false, true>(kd, p, &hits, nullptr, &counters);
    const double g = double(packets.size());
    state.counters["steps_per_group"] = double(counters.stream.group_steps) / g;
    state.counters["leaves_per_group"] = double(counters.stream.group_leaves) / g;
    state.counters["tests_per_group"] = double(counters.triangle_tests) / g;
}

void bm_diffuse_stream(benchmark::State& state, const std::string& name, bool loose_groups, bool wide_bvh) {
    DiffuseCase& c = diffuse_case(name);
    if (!c.error.empty()) return state.SkipWithError(c.error.c_str());
    StreamSettings settings;
    settings.group_loose_rays = loose_groups;
    settings.wide_bvh = wide_bvh;
    const StreamTracer tracer(*c.tree, settings);
    std::vector<Hit> hits(c.shuffled.size());
    for (auto _ : state) {
        tracer.intersect(c.shuffled, hits);
        benchmark::DoNotOptimize(hits.data());
    }
    per_ray(state, c.shuffled.size());
}

void register_benchmarks() {
    for (const char* scene : kScenes) {
        const std::string name = scene;
        auto reg = [&](const char* term, auto f) {
            benchmark::RegisterBenchmark((name + "/" + term).c_str(), f)->Unit(benchmark::kMicrosecond);
        };
        reg("shared_points", [name](benchmark::State& s) { bm_shared_points(s, name); });
        reg("keys", [name](benchmark::State& s) { bm_keys(s, name, best_isa()); });
        reg("keys_scalar", [name](benchmark::State& s) { bm_keys(s, name, Isa::scalar); });
        reg("radix_sort", [name](benchmark::State& s) { bm_radix_sort(s, name); });
        reg("gather", [name](benchmark::State& s) { bm_gather(s, name); });
        reg("sort_rays", [name](benchmark::State& s) { bm_sort_rays(s, name); });
        reg("cut_groups", [name](benchmark::State& s) { bm_cut_groups(s, name); });
        reg("origin_group", [name](benchmark::State& s) { bm_origin_group(s, name); });
        reg("single_sorted", [name](benchmark::State& s) { bm_single(s, name, true); });
        reg("single_shuffled", [name](benchmark::State& s) { bm_single(s, name, false); });
        reg("bvh_sorted", [name](benchmark::State& s) { bm_bvh(s, name, true); });
        reg("bvh_shuffled", [name](benchmark::State& s) { bm_bvh(s, name, false); });
        reg("stream", [name](benchmark::State& s) { bm_stream(s, name); });
        reg("shadow_bvh_packets", [name](benchmark::State& s) { bm_shadow_packets(s, name, true); });
        reg("shadow_bvh_rays", [name](benchmark::State& s) { bm_shadow_packets(s, name, false); });
        reg("shadow_mlrta", [name](benchmark::State& s) { bm_shadow_mlrta(s, name); });
        reg("embree_ao_shuffled", [name](benchmark::State& s) {
            StreamCase& c = stream_case(name);
            if (usable(s, c)) embree_rays(s, *c.tree, c.rays, true);
        });
        reg("embree_diffuse_shuffled", [name](benchmark::State& s) {
            DiffuseCase& c = diffuse_case(name);
            if (!c.error.empty()) return s.SkipWithError(c.error.c_str());
            embree_rays(s, *c.tree, c.shuffled, false);
        });
        reg("embree_diffuse_hot", [name](benchmark::State& s) {
            DiffuseCase& c = diffuse_case(name);
            if (!c.error.empty()) return s.SkipWithError(c.error.c_str());
            const std::size_t n = std::min<std::size_t>(1024, c.by_origin.size());
            embree_rays(s, *c.tree, std::vector<Ray>(c.by_origin.begin(), c.by_origin.begin() + std::ptrdiff_t(n)),
                        false);
        });
        reg("diffuse_single", [name](benchmark::State& s) { bm_diffuse_single(s, name); });
        const int leaf = bvh::WideBvhSettings{}.max_leaf_triangles;
        reg("diffuse_bvh", [name, leaf](benchmark::State& s) { bm_diffuse_bvh(s, name, false, leaf); });
        reg("diffuse_bvh_shuffled", [name, leaf](benchmark::State& s) { bm_diffuse_bvh(s, name, true, leaf); });
        reg("diffuse_bvh_hot", [name, leaf](benchmark::State& s) {
            DiffuseCase& c = diffuse_case(name);
            if (!c.error.empty()) return s.SkipWithError(c.error.c_str());
            const std::size_t n = std::min<std::size_t>(1024, c.by_origin.size());
            const std::vector<Ray> few(c.by_origin.begin(), c.by_origin.begin() + std::ptrdiff_t(n));
            bvh_rays(s, *c.tree, few, false, leaf);
        });
        for (int other : {4, 8, 16})
            reg(("diffuse_bvh_leaf" + std::to_string(other)).c_str(),
                [name, other](benchmark::State& s) { bm_diffuse_bvh(s, name, false, other); });
        reg("diffuse_group", [name](benchmark::State& s) { bm_diffuse_group(s, name); });
        reg("diffuse_stream", [name](benchmark::State& s) { bm_diffuse_stream(s, name, true, true); });
        reg("diffuse_stream_kd", [name](benchmark::State& s) { bm_diffuse_stream(s, name, true, false); });
        reg("diffuse_stream_singles", [name](benchmark::State& s) { bm_diffuse_stream(s, name, false, false); });
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
