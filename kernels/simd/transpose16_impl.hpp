#pragma once
// A 16 x 16 transpose of 32-bit words in AVX-512 registers: on return v[j] holds word j of every
// input register (lane i of v[j] = word j of the old v[i]). 64 shuffles: 32-bit unpacks, 64-bit
// unpacks, two rounds of 128-bit lane shuffles. Included only by units compiled for AVX-512.
#include <immintrin.h>

namespace beamtrace::simd {
namespace {

#if defined(__AVX512F__)
[[maybe_unused]] inline void transpose16_epi32(__m512i (&v)[16]) {
    __m512i t[16];
    for (int i = 0; i < 8; ++i) {
        t[2 * i] = _mm512_unpacklo_epi32(v[2 * i], v[2 * i + 1]);
        t[2 * i + 1] = _mm512_unpackhi_epi32(v[2 * i], v[2 * i + 1]);
    }
    // v[4 j + c], 128-bit lane L: words 4 L + c of the rows 4 j .. 4 j + 3.
    for (int j = 0; j < 4; ++j) {
        v[4 * j + 0] = _mm512_unpacklo_epi64(t[4 * j], t[4 * j + 2]);
        v[4 * j + 1] = _mm512_unpackhi_epi64(t[4 * j], t[4 * j + 2]);
        v[4 * j + 2] = _mm512_unpacklo_epi64(t[4 * j + 1], t[4 * j + 3]);
        v[4 * j + 3] = _mm512_unpackhi_epi64(t[4 * j + 1], t[4 * j + 3]);
    }
    for (int c = 0; c < 4; ++c) {
        const __m512i a = _mm512_shuffle_i32x4(v[c], v[4 + c], 0x44), b = _mm512_shuffle_i32x4(v[c], v[4 + c], 0xEE);
        const __m512i e = _mm512_shuffle_i32x4(v[8 + c], v[12 + c], 0x44),
                      d = _mm512_shuffle_i32x4(v[8 + c], v[12 + c], 0xEE);
        t[0 + c] = _mm512_shuffle_i32x4(a, e, 0x88);
        t[4 + c] = _mm512_shuffle_i32x4(a, e, 0xDD);
        t[8 + c] = _mm512_shuffle_i32x4(b, d, 0x88);
        t[12 + c] = _mm512_shuffle_i32x4(b, d, 0xDD);
    }
    for (int i = 0; i < 16; ++i) v[i] = t[i];
}
#endif

}  // namespace
}  // namespace beamtrace::simd
