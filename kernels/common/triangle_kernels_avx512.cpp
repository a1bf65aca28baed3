// AVX-512 kernels: the whole 4x4 packet in one register.
#include <immintrin.h>

#include "common/triangle_kernels_impl.hpp"

namespace beamtrace {
namespace simd {
template <>
inline std::uint32_t lane_bits<xsimd::avx512bw>(const xsimd::batch_bool<float, xsimd::avx512bw>& m) {
    return std::uint32_t(static_cast<__mmask16>(m));
}
}  // namespace simd

namespace kernels_avx512 {
void packet_x1(const WatertightPacket16& p, const Triangle& tri, LaneHits& out) {
    simd::packet_x1<xsimd::avx512bw>(p, tri, out);
}
}  // namespace kernels_avx512
}  // namespace beamtrace
