// SSE4.2 kernels (compiled with -msse4.2 only): 4 lanes.
#include "common/lane_bits.hpp"
#include "common/triangle_kernels_impl.hpp"

namespace beamtrace {
namespace kernels_sse42 {
void ray_x4(const WatertightRay& r, const Triangle* const* tris, int n, LaneHits& out) {
    out.mask = 0;
    simd::ray_xw<xsimd::sse4_2>(r, tris, n, out, 0);
}
void ray_x8(const WatertightRay& r, const Triangle* const* tris, int n, LaneHits& out) {
    out.mask = 0;
    simd::ray_xw<xsimd::sse4_2>(r, tris, n < 4 ? n : 4, out, 0);
    if (n > 4) simd::ray_xw<xsimd::sse4_2>(r, tris + 4, n - 4, out, 4);
}
void packet_x1(const WatertightPacket16& p, const Triangle& tri, LaneHits& out) {
    simd::packet_x1<xsimd::sse4_2>(p, tri, out);
}
}  // namespace kernels_sse42
}  // namespace beamtrace
