// AVX2 kernels (compiled with -mavx2 -mfma; contraction is off, so no FMA is emitted): 8 lanes.
#include "common/lane_bits.hpp"
#include "common/triangle_kernels_impl.hpp"

namespace beamtrace {
namespace kernels_avx2 {
void ray_x8(const WatertightRay& r, const Triangle* const* tris, int n, LaneHits& out) {
    out.mask = 0;
    simd::ray_xw<xsimd::avx2>(r, tris, n, out, 0);
}
void packet_x1(const WatertightPacket16& p, const Triangle& tri, LaneHits& out) {
    simd::packet_x1<xsimd::avx2>(p, tri, out);
}
}  // namespace kernels_avx2
}  // namespace beamtrace
