#pragma once
// The AVX-512 kernels of tile_ray_batch.hpp; included only by simd_avx512.cpp.
//   candidates: footprints compared 16 at a time, the passing ids compressed into the pair list
//               (stored 16 at a time: the list has room), repeats within the 16 dropped by a
//               conflict detection;
//   test:       16 pairs per step; each lane's ray taken from the batch's registers by a permute
//               (its origin already permuted to its axes), its triangle's corners gathered with the
//               lane's own axis permutation folded into the offsets, then the library's watertight
//               core (common/triangle_kernels_impl.hpp).
#include <cstdint>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

#include "common/triangle_kernels_impl.hpp"
#include "vlf/build/packed_ids_impl.hpp"
#include "vlf/stream/tile_ray_batch.hpp"

namespace beamtrace::vlf {
namespace {

#if defined(__AVX512BW__) && defined(__AVX512CD__)
[[maybe_unused]] std::uint32_t batch_candidates_avx512(const std::uint32_t* groups, const std::uint32_t* footprints,
                                                       PackedIds ids, std::uint32_t first,
                                                       std::uint32_t count, std::uint32_t ray_footprint, bool distinct,
                                                       std::uint32_t lane, std::uint32_t* out_ids,
                                                       std::uint32_t* out_lanes) {
    const __m512i r = _mm512_set1_epi32(int(ray_footprint));
    const __m512i l = _mm512_set1_epi32(int(lane));
    const std::uint32_t end = first + count, g0 = first / 16, g1 = (end + 15) / 16;
    std::uint32_t n = 0;
    // The live entries of the 16 from `at`: passing ids (without repeats unless distinct) appended.
    auto take = [&](std::uint32_t at, __mmask16 live) {
        const __m512i f = _mm512_maskz_loadu_epi32(live, footprints + at);
        const __mmask16 pass = _mm512_mask_cmpeq_epi32_mask(live, _mm512_max_epu8(f, r), r);
        if (pass == 0) return;
        __m512i v = _mm512_maskz_compress_epi32(pass, load_packed_ids(ids + at, live));
        std::uint32_t found = std::uint32_t(__builtin_popcount(pass));
        if (!distinct && found > 1) {
            const __mmask16 valid = __mmask16((1u << found) - 1u);
            const __m512i conflicts = _mm512_maskz_conflict_epi32(valid, v);
            const __mmask16 once = _mm512_mask_testn_epi32_mask(valid, conflicts, conflicts);
            v = _mm512_maskz_compress_epi32(once, v);
            found = std::uint32_t(__builtin_popcount(once));
        }
        _mm512_storeu_si512(out_ids + n, v);
        _mm512_storeu_si512(out_lanes + n, l);
        n += found;
    };
    if (groups == nullptr || g1 - g0 <= kDirectGroups) {  // short runs: 16 entries at a time from `first`
        for (std::uint32_t k = first; k < end; k += 16)
            take(k, end - k >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << (end - k)) - 1u));
        return n;
    }
    // Group g: its entries in [first, end).
    auto group = [&](std::uint32_t g) {
        const std::uint32_t b = 16 * g;
        const std::uint32_t lo = first > b ? first - b : 0, hi = end - b < 16 ? end - b : 16;
        take(b, __mmask16(((1u << hi) - 1u) & ~((1u << lo) - 1u)));
    };
    // Longer runs: the groups' union footprints first, 16 at a time.
    for (std::uint32_t h = g0; h < g1; h += 16) {
        const __mmask16 live = g1 - h >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << (g1 - h)) - 1u);
        const __m512i u = _mm512_maskz_loadu_epi32(live, groups + h);
        for (std::uint32_t m = _mm512_mask_cmpeq_epi32_mask(live, _mm512_max_epu8(u, r), r); m; m &= m - 1)
            group(h + std::uint32_t(__builtin_ctz(m)));
    }
    return n;
}

[[maybe_unused]] std::uint32_t batch_test_avx512(const TileRayBatch& rays, const Triangle* triangles,
                                                 const std::uint32_t* ids, const std::uint32_t* lanes,
                                                 std::uint32_t count, std::uint32_t occluded) {
    using Arch = xsimd::avx512bw;
    using B = xsimd::batch<float, Arch>;
    const __m512 okx = _mm512_load_ps(rays.okx), oky = _mm512_load_ps(rays.oky), okz = _mm512_load_ps(rays.okz);
    const __m512 sx = _mm512_load_ps(rays.sx), sy = _mm512_load_ps(rays.sy), sz = _mm512_load_ps(rays.sz);
    const __m512 tnear = _mm512_load_ps(rays.tnear), tfar = _mm512_load_ps(rays.tfar);
    const __m512i kx = _mm512_load_si512(rays.kx), ky = _mm512_load_si512(rays.ky), kz = _mm512_load_si512(rays.kz);
    const float* base = &triangles[0].v0.x;
    const __m512i one = _mm512_set1_epi32(1);
    for (std::uint32_t p = 0; p < count; p += 16) {
        __mmask16 live = count - p >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << (count - p)) - 1u);
        const __m512i lane = _mm512_maskz_loadu_epi32(live, lanes + p);
        // Pairs of rays found occluded already are left out.
        const __m512i done = _mm512_and_si512(_mm512_srlv_epi32(_mm512_set1_epi32(int(occluded)), lane), one);
        live = _mm512_mask_testn_epi32_mask(live, done, done);
        if (live == 0) continue;
        const __m512i id = _mm512_maskz_loadu_epi32(live, ids + p);
        const __m512i at = _mm512_mullo_epi32(id, _mm512_set1_epi32(9));
        const __m512i axis[3] = {_mm512_permutexvar_epi32(lane, kx), _mm512_permutexvar_epi32(lane, ky),
                                 _mm512_permutexvar_epi32(lane, kz)};
        const B o[3] = {B(_mm512_permutexvar_ps(lane, okx)), B(_mm512_permutexvar_ps(lane, oky)),
                        B(_mm512_permutexvar_ps(lane, okz))};
        const simd::Corners<Arch> k = simd::make_corners<Arch>([&](int c, int slot) {
            const __m512i index = _mm512_add_epi32(_mm512_add_epi32(at, axis[slot]), _mm512_set1_epi32(3 * c));
            return B(_mm512_mask_i32gather_ps(_mm512_setzero_ps(), live, index, base, 4)) - o[slot];
        });
        LaneHits hits;
        const std::uint32_t bits =
            simd::watertight_core<Arch>(k, B(_mm512_permutexvar_ps(lane, sx)), B(_mm512_permutexvar_ps(lane, sy)),
                                        B(_mm512_permutexvar_ps(lane, sz)), B(_mm512_permutexvar_ps(lane, tnear)),
                                        B(_mm512_permutexvar_ps(lane, tfar)), std::uint32_t(live), hits, 0);
        for (std::uint32_t m = bits; m; m &= m - 1) occluded |= 1u << lanes[p + std::uint32_t(__builtin_ctz(m))];
    }
    return occluded;
}
#endif

}  // namespace
}  // namespace beamtrace::vlf
