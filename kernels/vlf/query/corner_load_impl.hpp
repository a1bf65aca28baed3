#pragma once
// The corners of up to 16 triangles for one ray's AVX-512 watertight test (lanes `lanes` of ids),
// minus the ray's origin and permuted to its axes; included only by the AVX-512 kernels. A few
// triangles are copied lane by lane, more are gathered: on some processors (AMD Zen 4) a 16-lane
// gather costs about as much as copying eight triangles. Either way the lanes hold the same values,
// so the test gives the same bits.
#include <cstdint>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

#include "beamtrace/scene.hpp"
#include "common/triangle_kernels_impl.hpp"
#include "common/watertight_ray.hpp"

namespace beamtrace::vlf {
namespace {

#if defined(__AVX512F__)
inline constexpr int kCopiedCorners = 6;  // at most this many triangles are copied, not gathered

[[gnu::always_inline]] inline simd::Corners<xsimd::avx512bw> ray_corners(const WatertightRay& ray,
                                                                         const Triangle* triangles,
                                                                         const std::uint32_t* ids, __mmask16 lanes) {
    using B = xsimd::batch<float, xsimd::avx512bw>;
    const float* o = &ray.org.x;
    const int axis[3] = {ray.kx, ray.ky, ray.kz};
    if (__builtin_popcount(lanes) <= kCopiedCorners) {
        alignas(64) float comp[9][16];  // only the lanes in `lanes` are written, and read
        for (std::uint32_t m = lanes; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            const float* v = &triangles[ids[i]].v0.x;
            for (int c = 0; c < 9; ++c) comp[c][i] = v[c];
        }
        return simd::make_corners<xsimd::avx512bw>([&](int c, int slot) {
            const int a = axis[slot];
            return B(_mm512_maskz_load_ps(lanes, comp[3 * c + a])) - B(o[a]);
        });
    }
    const __m512i at = _mm512_mullo_epi32(_mm512_maskz_loadu_epi32(lanes, ids), _mm512_set1_epi32(9));
    const float* base = &triangles[0].v0.x;
    return simd::make_corners<xsimd::avx512bw>([&](int c, int slot) {
        const int a = axis[slot];
        const __m512i index = _mm512_add_epi32(at, _mm512_set1_epi32(3 * c + a));
        return B(_mm512_mask_i32gather_ps(_mm512_setzero_ps(), lanes, index, base, 4)) - B(o[a]);
    });
}
#endif

}  // namespace
}  // namespace beamtrace::vlf
