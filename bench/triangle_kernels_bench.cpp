// Micro-benchmarks of the watertight ray/triangle kernels (kernels/common/triangle_kernels.hpp) for
// every instruction set this CPU runs, the scalar reference among them, and beside them Embree's
// rtcIntersect1 / rtcIntersect16 on scenes of the same triangles (through oracle::EmbreeOracle, so
// Embree's figures include its per-call overhead: the wrapper, the intersect context, the BVH).
//
// The rays and triangles are pseudo-random, generated once (never timed) and the same for every
// benchmark: ray i meets the triangles of group i % kGroups (ray_x4, ray_x8); packet p (rays 16p to
// 16p + 15) meets triangle p % kPacketTriangles (packet_x1). Every benchmark reports
// items_processed = ray/triangle tests, so Google Benchmark prints tests per second, and the kernel
// benchmarks report hit_rate = hits / tests (the same for every ISA: the kernels are bit-exact).
#include <benchmark/benchmark.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"
#include "simd/isa.hpp"
#include "common/triangle_kernels.hpp"
#include "common/watertight_ray.hpp"
#include "oracle/embree_oracle.hpp"
#include "scenes/deterministic_random.hpp"

namespace {

using beamtrace::Float3;
using beamtrace::Isa;
using beamtrace::LaneHits;
using beamtrace::Packet16;
using beamtrace::Ray;
using beamtrace::Triangle;
using beamtrace::TriangleKernels;
using beamtrace::WatertightPacket16;
using beamtrace::WatertightRay;

constexpr int kRays = 2048;  // rays in the pool (kRays / 16 packets)
constexpr int kPackets = kRays / 16;
constexpr int kGroups = 32;           // groups of 8 triangles (64 groups of 4 for ray_x4)
constexpr int kPacketTriangles = 32;  // the first triangles of the pool, for packet_x1
constexpr int kTriangles = kGroups * 8;

// Geometry of the pool, tuned for a hit rate of about 40% per ray/triangle test: roughly equilateral
// triangles in random planes (circumradius kTriangleRadius, +-30%, corners +-0.3 rad off the regular
// angles) centred uniformly in a ball of radius kCentreRadius; ray origins on a sphere of radius
// kEyeDistance, each ray aimed at a uniform point of a ball of radius kTargetRadius.
constexpr float kCentreRadius = 0.6f;
constexpr float kTriangleRadius = 0.9f;
constexpr float kEyeDistance = 5.0f;
constexpr float kTargetRadius = 0.4f;

using Random = beamtrace::scenes::DeterministicRandom;

Float3 in_unit_ball(Random& rng) {
    for (;;) {
        const Float3 p{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
        if (beamtrace::dot(p, p) <= 1.0f && beamtrace::dot(p, p) > 1e-6f) return p;
    }
}

Triangle random_triangle(Random& rng) {
    const Float3 centre = kCentreRadius * in_unit_ball(rng);
    const Float3 normal = beamtrace::normalize(in_unit_ball(rng));
    Float3 side = beamtrace::cross(normal, in_unit_ball(rng));
    while (beamtrace::dot(side, side) < 1e-4f) side = beamtrace::cross(normal, in_unit_ball(rng));
    const Float3 e1 = beamtrace::normalize(side), e2 = beamtrace::cross(normal, e1);
    const float radius = kTriangleRadius * rng.uniform(0.7f, 1.3f);
    const float phase = rng.uniform(0.0f, 2.0f * std::numbers::pi_v<float>);
    Float3 corner[3];
    for (int k = 0; k < 3; ++k) {
        const float angle = phase + float(k) * (2.0f / 3.0f) * std::numbers::pi_v<float> + rng.uniform(-0.3f, 0.3f);
        corner[k] = centre + radius * (std::cos(angle) * e1 + std::sin(angle) * e2);
    }
    return Triangle{corner[0], corner[1], corner[2]};
}

// Everything the benchmarks read, built on first use.
struct Pool {
    std::vector<Triangle> triangles;           // kTriangles
    std::vector<const Triangle*> pointers;     // &triangles[i]: group g of n = pointers[g*n, g*n+n)
    std::vector<Ray> rays;                     // kRays
    std::vector<WatertightRay> wrays;          // the same rays, set up for the kernels
    std::vector<Packet16> packets;             // kPackets, all lanes active
    std::vector<WatertightPacket16> wpackets;  // the same packets, set up for the kernels
    std::vector<std::unique_ptr<beamtrace::oracle::EmbreeOracle>> embree8;  // one per group of 8
    std::vector<std::unique_ptr<beamtrace::oracle::EmbreeOracle>> embree1;  // one per packet triangle

    Pool() {
        Random rng(20240611u);
        triangles.reserve(kTriangles);
        for (int i = 0; i < kTriangles; ++i) triangles.push_back(random_triangle(rng));
        for (const Triangle& t : triangles) pointers.push_back(&t);
        for (int i = 0; i < kRays; ++i) {
            const Float3 org = kEyeDistance * beamtrace::normalize(in_unit_ball(rng));
            const Float3 target = kTargetRadius * in_unit_ball(rng);
            rays.push_back(Ray{org, 0.0f, beamtrace::normalize(target - org), beamtrace::kInfinity});
            wrays.push_back(beamtrace::make_watertight_ray(rays.back()));
        }
        packets.resize(kPackets);
        for (int p = 0; p < kPackets; ++p) {
            for (int i = 0; i < 16; ++i) packets[p].set_ray(i, rays[p * 16 + i]);
            packets[p].active = 0xFFFFu;
            wpackets.push_back(beamtrace::make_watertight_packet(packets[p]));
        }
        for (int g = 0; g < kGroups; ++g) embree8.push_back(embree_scene(g * 8, 8));
        for (int t = 0; t < kPacketTriangles; ++t) embree1.push_back(embree_scene(t, 1));
    }

    // An Embree scene of exactly `count` triangles of the pool, starting at `first` (triangle k of
    // the Embree scene is triangles[first + k]).
    std::unique_ptr<beamtrace::oracle::EmbreeOracle> embree_scene(int first, int count) const {
        std::vector<Float3> vertices;
        std::vector<std::uint32_t> indices;
        for (int k = 0; k < count; ++k) {
            const Triangle& t = triangles[first + k];
            for (const Float3& v : {t.v0, t.v1, t.v2}) {
                indices.push_back(std::uint32_t(vertices.size()));
                vertices.push_back(v);
            }
        }
        auto oracle = std::make_unique<beamtrace::oracle::EmbreeOracle>(beamtrace::Scene(vertices, indices));
        if (oracle->embree_triangle_count() != std::size_t(count))
            throw std::runtime_error("a pool triangle is degenerate: the Embree scene lacks triangles");
        return oracle;
    }
};

const Pool& pool() {
    static const Pool p;
    return p;
}

const char* kEmbreeLabel = "Embree (includes its per-call overhead)";

// Label of a kernel: the scalar reference, or which ISA's kernel this table entry really calls when
// it is shared with a narrower ISA (ray_x4 is SSE4.2 for every wider ISA, ray_x8 is AVX2 for AVX-512).
std::string kernel_label(Isa isa, int which) {
    if (isa == Isa::scalar) return "scalar reference (intersect_triangle per lane)";
    const TriangleKernels& k = beamtrace::triangle_kernels(isa);
    for (Isa narrower : {Isa::sse42, Isa::avx2}) {
        if (int(narrower) >= int(isa)) break;
        const TriangleKernels& n = beamtrace::triangle_kernels(narrower);
        const bool same = which == 4   ? n.ray_x4 == k.ray_x4
                          : which == 8 ? n.ray_x8 == k.ray_x8
                                       : n.packet_x1 == k.packet_x1;
        if (same) return std::string("same function as ") + beamtrace::isa_name(narrower);
    }
    return {};
}

// One pass of a kernel over the pool; returns the sum of the hit masks (cheap to keep, so that the
// timed loop does nothing else) or, with kCountHits, the number of hits.
template <bool kCountHits>
std::uint64_t ray_xn_pass(const Pool& p, decltype(TriangleKernels::ray_x8) kernel, int n) {
    const int groups = kTriangles / n;  // a power of two
    LaneHits hits;
    std::uint64_t sum = 0;
    for (int i = 0; i < kRays; ++i) {
        kernel(p.wrays[i], p.pointers.data() + (i & (groups - 1)) * n, n, hits);
        sum += kCountHits ? unsigned(std::popcount(hits.mask)) : hits.mask;
    }
    return sum;
}

template <bool kCountHits>
std::uint64_t packet_x1_pass(const Pool& p, decltype(TriangleKernels::packet_x1) kernel) {
    LaneHits hits;
    std::uint64_t sum = 0;
    for (int i = 0; i < kPackets; ++i) {
        kernel(p.wpackets[i], p.triangles[i & (kPacketTriangles - 1)], hits);
        sum += kCountHits ? unsigned(std::popcount(hits.mask)) : hits.mask;
    }
    return sum;
}

// One ray against n = 4 or 8 triangles per call.
void bm_ray_xn(benchmark::State& state, Isa isa, int n) {
    const Pool& p = pool();
    const TriangleKernels& k = beamtrace::triangle_kernels(isa);
    const auto kernel = n == 4 ? k.ray_x4 : k.ray_x8;
    std::uint64_t sink = 0;
    for (auto _ : state) {
        sink += ray_xn_pass<false>(p, kernel, n);
        benchmark::DoNotOptimize(sink);
    }
    state.SetItemsProcessed(state.iterations() * kRays * n);
    state.counters["hit_rate"] = double(ray_xn_pass<true>(p, kernel, n)) / (double(kRays) * n);
    state.SetLabel(kernel_label(isa, n));
}

// The 16 rays of a packet against one triangle per call.
void bm_packet_x1(benchmark::State& state, Isa isa) {
    const Pool& p = pool();
    const auto kernel = beamtrace::triangle_kernels(isa).packet_x1;
    std::uint64_t sink = 0;
    for (auto _ : state) {
        sink += packet_x1_pass<false>(p, kernel);
        benchmark::DoNotOptimize(sink);
    }
    state.SetItemsProcessed(state.iterations() * kPackets * 16);
    state.counters["hit_rate"] = double(packet_x1_pass<true>(p, kernel)) / (double(kPackets) * 16);
    state.SetLabel(kernel_label(isa, 16));
}

// rtcIntersect1 of each ray on the 8-triangle Embree scene of its group, counted as 8 tests per call
// (the work ray_x8 does for the same answer; Embree's BVH may cull some of them).
// ray_hit_rate = rays that hit any of the 8 (not comparable with the kernels' per-test hit_rate).
void bm_embree_intersect1(benchmark::State& state) {
    const Pool& p = pool();
    std::uint64_t hit_count = 0;
    for (auto _ : state) {
        for (int i = 0; i < kRays; ++i) hit_count += p.embree8[i & (kGroups - 1)]->intersect1(p.rays[i]).hit();
        benchmark::DoNotOptimize(hit_count);
    }
    const double rays = double(state.iterations()) * kRays;
    state.SetItemsProcessed(std::int64_t(rays * 8));
    state.counters["ray_hit_rate"] = rays > 0 ? double(hit_count) / rays : 0.0;
    state.SetLabel(kEmbreeLabel);
}

// rtcIntersect16 of each packet on the 1-triangle Embree scene of its triangle: 16 tests per call,
// the same pairs as packet_x1, so hit_rate must match the kernels' (up to hits on edges).
void bm_embree_intersect16(benchmark::State& state) {
    const Pool& p = pool();
    beamtrace::PacketHits16 hits;
    std::uint64_t hit_count = 0;
    for (auto _ : state) {
        for (int i = 0; i < kPackets; ++i) {
            p.embree1[i & (kPacketTriangles - 1)]->intersect16(p.packets[i], hits);
            for (int lane = 0; lane < 16; ++lane) hit_count += hits.triangle[lane] != beamtrace::kNoHit;
        }
        benchmark::DoNotOptimize(hit_count);
    }
    const double tests = double(state.iterations()) * kPackets * 16;
    state.SetItemsProcessed(std::int64_t(tests));
    state.counters["hit_rate"] = tests > 0 ? double(hit_count) / tests : 0.0;
    state.SetLabel(kEmbreeLabel);
}

std::vector<Isa> available_isas() {
    std::vector<Isa> isas;
    for (Isa isa : {Isa::scalar, Isa::sse42, Isa::avx2, Isa::avx512})
        if (beamtrace::isa_available(isa)) isas.push_back(isa);
    return isas;
}

void register_benchmarks() {
    const std::vector<Isa> isas = available_isas();
    for (Isa isa : isas)
        benchmark::RegisterBenchmark((std::string("ray_x4/") + beamtrace::isa_name(isa)).c_str(),
                                     [isa](benchmark::State& s) { bm_ray_xn(s, isa, 4); });
    for (Isa isa : isas)
        benchmark::RegisterBenchmark((std::string("ray_x8/") + beamtrace::isa_name(isa)).c_str(),
                                     [isa](benchmark::State& s) { bm_ray_xn(s, isa, 8); });
    benchmark::RegisterBenchmark("ray_x8/embree_intersect1", bm_embree_intersect1);
    for (Isa isa : isas)
        benchmark::RegisterBenchmark((std::string("packet_x1/") + beamtrace::isa_name(isa)).c_str(),
                                     [isa](benchmark::State& s) { bm_packet_x1(s, isa); });
    benchmark::RegisterBenchmark("packet_x1/embree_intersect16", bm_embree_intersect16);
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
