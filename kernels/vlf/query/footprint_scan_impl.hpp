#pragma once
// The footprint scan (tile_footprint.hpp) over a run of entries, per instruction set: the indices
// of the entries whose footprint meets the ray's. Included only by the per-ISA units.
#include <cstdint>

#include <immintrin.h>

namespace beamtrace::vlf {
namespace {

// footprints[k] passes when every byte is <= the ray's byte: max(f, ray) == ray per 32-bit lane.
[[maybe_unused]] std::uint32_t scan_sse42(const std::uint32_t* footprints, std::uint32_t count, std::uint32_t ray,
                                          std::uint32_t* passing) {
    const __m128i r = _mm_set1_epi32(int(ray));
    std::uint32_t n = 0, k = 0;
    for (; k + 4 <= count; k += 4) {
        const __m128i f = _mm_loadu_si128(reinterpret_cast<const __m128i*>(footprints + k));
        for (unsigned m = unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_max_epu8(f, r), r)))); m;
             m &= m - 1)
            passing[n++] = k + unsigned(__builtin_ctz(m));
    }
    for (; k < count; ++k) {
        const std::uint32_t f = footprints[k];
        bool pass = true;
        for (int shift = 0; shift < 32; shift += 8) pass &= ((f >> shift) & 0xFFu) <= ((ray >> shift) & 0xFFu);
        if (pass) passing[n++] = k;
    }
    return n;
}

#if defined(__AVX2__)
[[maybe_unused]] std::uint32_t scan_avx2(const std::uint32_t* footprints, std::uint32_t count, std::uint32_t ray,
                                         std::uint32_t* passing) {
    const __m256i r = _mm256_set1_epi32(int(ray));
    std::uint32_t n = 0, k = 0;
    for (; k + 8 <= count; k += 8) {
        const __m256i f = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(footprints + k));
        const __m256i ok = _mm256_cmpeq_epi32(_mm256_max_epu8(f, r), r);
        for (unsigned m = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(ok))); m; m &= m - 1)
            passing[n++] = k + unsigned(__builtin_ctz(m));
    }
    const std::uint32_t tail = scan_sse42(footprints + k, count - k, ray, passing + n);
    for (std::uint32_t i = 0; i < tail; ++i) passing[n + i] += k;
    return n + tail;
}
#endif

#if defined(__AVX512BW__)
[[maybe_unused]] std::uint32_t scan_avx512(const std::uint32_t* footprints, std::uint32_t count, std::uint32_t ray,
                                           std::uint32_t* passing) {
    const __m512i r = _mm512_set1_epi32(int(ray));
    const __m512i step = _mm512_set1_epi32(16);
    __m512i index = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    std::uint32_t n = 0;
    for (std::uint32_t k = 0; k < count; k += 16) {
        const __mmask16 live = count - k >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << (count - k)) - 1u);
        const __m512i f = _mm512_maskz_loadu_epi32(live, footprints + k);
        const __mmask16 ok = _mm512_mask_cmpeq_epi32_mask(live, _mm512_max_epu8(f, r), r);
        // Compress in a register, store all 16 (passing has room for them): faster than a
        // compressing store to memory.
        _mm512_storeu_si512(passing + n, _mm512_maskz_compress_epi32(ok, index));
        n += std::uint32_t(__builtin_popcount(ok));
        index = _mm512_add_epi32(index, step);
    }
    return n;
}
#endif

}  // namespace
}  // namespace beamtrace::vlf
