// Packet frustum culling for one instruction set (compiled for it only; see kernels/CMakeLists.txt).
#include "mlrta/packet_frustum_impl.hpp"

namespace beamtrace::mlrta::frustum_cull_sse42 {
std::uint32_t misses(const PacketFrustum& f, const Triangle* tris, const std::uint32_t* ids, int n) {
    return simd::frustum_misses<xsimd::sse4_2>(f, tris, ids, n);
}
}  // namespace beamtrace::mlrta::frustum_cull_sse42
