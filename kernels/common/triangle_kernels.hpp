#pragma once
// SIMD watertight ray/triangle kernels, chosen at run time (SSE4.2 / AVX2 / AVX-512; simd/dispatch.hpp),
// each returning per lane exactly what intersect_triangle() (the scalar reference) returns.
#include <cstddef>
#include <cstdint>

#include "beamtrace/scene.hpp"
#include "simd/dispatch.hpp"
#include "simd/isa.hpp"
#include "common/watertight_ray.hpp"

namespace beamtrace {

// Per-lane results: bit i of mask set = lane i hit, with t[i], u[i], v[i].
struct alignas(64) LaneHits {
    float t[16], u[16], v[16];
    std::uint32_t mask = 0;
};

struct TriangleKernels {
    Isa isa;
    // One ray against n triangles (lane i tests tris[i]); n <= 4 for ray_x4, n <= 8 for ray_x8.
    void (*ray_x4)(const WatertightRay& ray, const Triangle* const* tris, int n, LaneHits& out);
    void (*ray_x8)(const WatertightRay& ray, const Triangle* const* tris, int n, LaneHits& out);
    // The 16 rays of a packet against one triangle; inactive rays never hit.
    void (*packet_x1)(const WatertightPacket16& rays, const Triangle& tri, LaneHits& out);
    // One ray against n <= 16 consecutive triangles stored as nine rows of corner components (row c,
    // component c % 3 of corner c / 3, starts at rows + c * stride; lane i tests triangle first + i),
    // a register at a time with plain loads (no copy into lanes): every row must be readable up to
    // first + 16 (kdtree::PacketTables pads them so).
    void (*ray_rows)(const WatertightRay& ray, const float* rows, std::size_t stride, std::size_t first, int n,
                     LaneHits& out);
};

// The kernels of one instruction set (which must be available), or of the best one.
const TriangleKernels& triangle_kernels(Isa isa);
inline const TriangleKernels& triangle_kernels() { return triangle_kernels(best_isa()); }

}  // namespace beamtrace

BEAMTRACE_KERNEL_TABLE(beamtrace::TriangleKernels);
