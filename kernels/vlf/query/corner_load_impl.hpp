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
    const int kx = ray.kx, ky = ray.ky, kz = ray.kz;
    simd::Corners<xsimd::avx512bw> k;
    if (__builtin_popcount(lanes) <= kCopiedCorners) {
        alignas(64) float comp[9][16];  // only the lanes in `lanes` are written, and read
        for (std::uint32_t m = lanes; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            const float* v = &triangles[ids[i]].v0.x;
            for (int c = 0; c < 9; ++c) comp[c][i] = v[c];
        }
        auto at = [&](int c, int axis) { return B(_mm512_maskz_load_ps(lanes, comp[3 * c + axis])) - B(o[axis]); };
        k.ax = at(0, kx);
        k.ay = at(0, ky);
        k.az = at(0, kz);
        k.bx = at(1, kx);
        k.by = at(1, ky);
        k.bz = at(1, kz);
        k.cx = at(2, kx);
        k.cy = at(2, ky);
        k.cz = at(2, kz);
        return k;
    }
    const __m512i at = _mm512_mullo_epi32(_mm512_maskz_loadu_epi32(lanes, ids), _mm512_set1_epi32(9));
    const float* base = &triangles[0].v0.x;
    auto corner = [&](int c, int axis) {
        const __m512i index = _mm512_add_epi32(at, _mm512_set1_epi32(3 * c + axis));
        return B(_mm512_mask_i32gather_ps(_mm512_setzero_ps(), lanes, index, base, 4)) - B(o[axis]);
    };
    k.ax = corner(0, kx);
    k.ay = corner(0, ky);
    k.az = corner(0, kz);
    k.bx = corner(1, kx);
    k.by = corner(1, ky);
    k.bz = corner(1, kz);
    k.cx = corner(2, kx);
    k.cy = corner(2, ky);
    k.cz = corner(2, kz);
    return k;
}
#endif

}  // namespace
}  // namespace beamtrace::vlf
