// Packet frustum culling for one instruction set (compiled for it only; see kernels/CMakeLists.txt).
#include "mlrta/packet_frustum_impl.hpp"

namespace beamtrace::mlrta::frustum_cull_avx2 {
std::uint32_t misses(const PacketFrustum& f, const Triangle* tris, const std::uint32_t* ids, int n) {
    return simd::frustum_misses<xsimd::avx2>(f, tris, ids, n);
}
}  // namespace beamtrace::mlrta::frustum_cull_avx2
