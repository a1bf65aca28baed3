// MLRTA's SIMD kernels for one instruction set (compiled for it only; see kernels/CMakeLists.txt):
// packet frustum culling of leaf triangles and the per-lane slab test of leaf boxes.
#include "mlrta/lane_slabs_impl.hpp"
#include "mlrta/packet_frustum_impl.hpp"

namespace beamtrace::mlrta {
namespace frustum_cull_avx2 {
std::uint32_t misses(const PacketFrustum& f, const Triangle* tris, int n) {
    return simd::frustum_misses<xsimd::avx2>(f, tris, n);
}
}  // namespace frustum_cull_avx2
namespace lane_slabs_avx2 {
std::uint32_t meeting(const LaneSlabs& s, const float* tfar, std::uint32_t lanes, const Box& box) {
    return simd::lanes_meeting<xsimd::avx2>(s, tfar, lanes, box);
}
}  // namespace lane_slabs_avx2
}  // namespace beamtrace::mlrta
