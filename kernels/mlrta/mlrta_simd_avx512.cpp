// MLRTA's SIMD kernels for one instruction set (compiled for it only; see kernels/CMakeLists.txt):
// packet frustum culling of leaf triangles and the per-lane slab test of leaf boxes.
// GCC 12 warns inside its own AVX-512 min/max intrinsics (the pass-through operand of the unmasked
// forms), as in vlf/simd_avx512.cpp.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include "mlrta/lane_slabs_impl.hpp"
#include "mlrta/packet_frustum_impl.hpp"

namespace beamtrace::mlrta {
namespace frustum_cull_avx512 {
std::uint32_t misses(const PacketFrustum& f, const Triangle* tris, int n) {
    return simd::frustum_misses<xsimd::avx512bw>(f, tris, n);
}
}  // namespace frustum_cull_avx512
namespace lane_slabs_avx512 {
std::uint32_t meeting(const LaneSlabs& s, const float* tfar, std::uint32_t lanes, const Box& box) {
    return simd::lanes_meeting<xsimd::avx512bw>(s, tfar, lanes, box);
}
}  // namespace lane_slabs_avx512
}  // namespace beamtrace::mlrta
#pragma GCC diagnostic pop
