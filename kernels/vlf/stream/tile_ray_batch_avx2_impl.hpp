#pragma once
// The AVX2 kernels of tile_ray_batch.hpp; included only by kernels_avx2.cpp. AVX2 has no compress
// and no conflict detection, so:
//   candidates: footprints compared 8 at a time (two compares per 16 of the reference's runs); the
//               few passing entries (about three per ray on AO streams) appended one by one, a
//               repeat within the 16 dropped by comparing with the pairs appended from them;
//   test:       8 pairs per step; each lane's ray taken from the batch's 16-lane arrays by two
//               in-register permutes and a blend, its triangle's corners gathered with the lane's
//               axis permutation folded into the offsets, then the library's watertight core
//               (common/triangle_kernels_impl.hpp).
// Same pairs in the same order, same bits as the scalar references (tests/vlf/vlf_kernels_test.cpp).
#include <cstdint>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

#include "common/triangle_kernels_impl.hpp"
#include "vlf/stream/tile_ray_batch.hpp"

namespace beamtrace::vlf {
namespace {

#if defined(__AVX2__)
// Lanes whose 32-bit word meets the ray's footprint (every byte of f at most r's: footprints_meet).
[[gnu::always_inline]] inline std::uint32_t meeting8(const std::uint32_t* words, std::uint32_t live, __m256i r) {
    if (live == 0) return 0;
    const __m256i load = _mm256_cmpgt_epi32(
        _mm256_and_si256(_mm256_set1_epi32(int(live)), _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128)),
        _mm256_setzero_si256());
    const __m256i f = _mm256_maskload_epi32(reinterpret_cast<const int*>(words), load);
    const __m256i meet = _mm256_cmpeq_epi32(_mm256_max_epu8(f, r), r);
    return std::uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(meet))) & live;
}

[[gnu::always_inline]] inline std::uint32_t meeting16(const std::uint32_t* words, std::uint32_t live, __m256i r) {
    return meeting8(words, live & 0xFFu, r) | (meeting8(words + 8, live >> 8, r) << 8);
}

[[maybe_unused]] std::uint32_t batch_candidates_avx2(const std::uint32_t* groups, const std::uint32_t* footprints,
                                                     PackedIds ids, std::uint32_t first, std::uint32_t count,
                                                     std::uint32_t ray_footprint, bool distinct, std::uint32_t lane,
                                                     std::uint32_t* out_ids, std::uint32_t* out_lanes) {
    const __m256i r = _mm256_set1_epi32(int(ray_footprint));
    const std::uint32_t end = first + count, g0 = first / 16, g1 = (end + 15) / 16;
    std::uint32_t n = 0;
    // The live entries of the 16 from `at`: passing ids (without repeats among them unless distinct) appended.
    auto take = [&](std::uint32_t at, std::uint32_t live) {
        const std::uint32_t start = n;
        for (std::uint32_t pass = meeting16(footprints + at, live, r); pass; pass &= pass - 1) {
            const std::uint32_t id = ids[at + std::uint32_t(__builtin_ctz(pass))];
            bool repeat = false;
            if (!distinct)
                for (std::uint32_t c = start; c < n; ++c) repeat |= out_ids[c] == id;
            if (repeat) continue;
            out_ids[n] = id;
            out_lanes[n] = lane;
            ++n;
        }
    };
    if (groups == nullptr || g1 - g0 <= kDirectGroups) {  // short runs: 16 entries at a time from `first`
        for (std::uint32_t k = first; k < end; k += 16) take(k, end - k >= 16 ? 0xFFFFu : (1u << (end - k)) - 1u);
        return n;
    }
    // Longer runs: the groups' union footprints first, 16 at a time; group g's entries in [first, end).
    for (std::uint32_t h = g0; h < g1; h += 16) {
        const std::uint32_t live = g1 - h >= 16 ? 0xFFFFu : (1u << (g1 - h)) - 1u;
        for (std::uint32_t m = meeting16(groups + h, live, r); m; m &= m - 1) {
            const std::uint32_t b = 16 * (h + std::uint32_t(__builtin_ctz(m)));
            const std::uint32_t lo = first > b ? first - b : 0, hi = end - b < 16 ? end - b : 16;
            take(b, ((1u << hi) - 1u) & ~((1u << lo) - 1u));
        }
    }
    return n;
}

// Entry lane[i] of a 16-lane array, per lane i of 8.
[[gnu::always_inline]] inline __m256 pick16(const float* array, __m256i lane) {
    const __m256 lo = _mm256_permutevar8x32_ps(_mm256_load_ps(array), lane);
    const __m256 hi = _mm256_permutevar8x32_ps(_mm256_load_ps(array + 8), lane);
    return _mm256_blendv_ps(lo, hi, _mm256_castsi256_ps(_mm256_cmpgt_epi32(lane, _mm256_set1_epi32(7))));
}
[[gnu::always_inline]] inline __m256i pick16(const std::int32_t* array, __m256i lane) {
    return _mm256_castps_si256(pick16(reinterpret_cast<const float*>(array), lane));
}

[[maybe_unused]] std::uint32_t batch_test_avx2(const TileRayBatch& rays, const Triangle* triangles,
                                               const std::uint32_t* ids, const std::uint32_t* lanes, std::uint32_t count,
                                               std::uint32_t occluded) {
    using Arch = xsimd::avx2;
    using B = xsimd::batch<float, Arch>;
    const float* base = &triangles[0].v0.x;
    const __m256i one = _mm256_set1_epi32(1), bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    for (std::uint32_t p = 0; p < count; p += 8) {
        const std::uint32_t in = count - p >= 8 ? 0xFFu : (1u << (count - p)) - 1u;
        const __m256i in_mask = _mm256_cmpgt_epi32(_mm256_and_si256(_mm256_set1_epi32(int(in)), bit), _mm256_setzero_si256());
        const __m256i lane = _mm256_maskload_epi32(reinterpret_cast<const int*>(lanes + p), in_mask);
        // Pairs of rays found occluded already are left out.
        const __m256i done = _mm256_and_si256(_mm256_srlv_epi32(_mm256_set1_epi32(int(occluded)), lane), one);
        const __m256i live_mask = _mm256_andnot_si256(_mm256_cmpeq_epi32(done, one), in_mask);
        const std::uint32_t live = std::uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(live_mask)));
        if (live == 0) continue;
        const __m256i id = _mm256_maskload_epi32(reinterpret_cast<const int*>(ids + p), live_mask);
        const __m256i at = _mm256_mullo_epi32(id, _mm256_set1_epi32(9));
        const __m256i axis[3] = {pick16(rays.kx, lane), pick16(rays.ky, lane), pick16(rays.kz, lane)};
        const B o[3] = {B(pick16(rays.okx, lane)), B(pick16(rays.oky, lane)), B(pick16(rays.okz, lane))};
        const simd::Corners<Arch> k = simd::make_corners<Arch>([&](int c, int slot) {
            const __m256i index = _mm256_add_epi32(_mm256_add_epi32(at, axis[slot]), _mm256_set1_epi32(3 * c));
            return B(_mm256_mask_i32gather_ps(_mm256_setzero_ps(), base, index, _mm256_castsi256_ps(live_mask), 4)) -
                   o[slot];
        });
        LaneHits hits;
        const std::uint32_t bits = simd::watertight_core<Arch>(
            k, B(pick16(rays.sx, lane)), B(pick16(rays.sy, lane)), B(pick16(rays.sz, lane)), B(pick16(rays.tnear, lane)),
            B(pick16(rays.tfar, lane)), live, hits, 0);
        for (std::uint32_t m = bits; m; m &= m - 1) occluded |= 1u << lanes[p + std::uint32_t(__builtin_ctz(m))];
    }
    return occluded;
}
#endif

}  // namespace
}  // namespace beamtrace::vlf
