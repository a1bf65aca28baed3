// AVX-512 kernels: the whole 4x4 packet in one register.
#include "common/lane_bits.hpp"
#include "common/triangle_kernels_impl.hpp"

namespace beamtrace {
namespace kernels_avx512 {
void packet_x1(const WatertightPacket16& p, const Triangle& tri, LaneHits& out) {
    simd::packet_x1<xsimd::avx512bw>(p, tri, out);
}
}  // namespace kernels_avx512
}  // namespace beamtrace
