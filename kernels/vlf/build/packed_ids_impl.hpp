#pragma once
// Sixteen packed ids (packed_ids.hpp) into the 32-bit lanes of one AVX-512 register; included only
// by the AVX-512 kernels. The bytes of the lanes from the lowest to the highest set bit of `live`
// are loaded (masked: nothing beyond them is touched), a dword permute gives each 128-bit lane the
// 12 bytes of its four ids, and a byte shuffle spreads them to one id a dword. Lanes outside
// `live` are zero, as a masked 32-bit load leaves them. The kernels pass the lanes of entries that
// exist (known before the footprints are compared), not the passing ones, so that the mask, the
// load and the shuffles wait for nothing; the compress by the passing lanes comes after.
#include <cstdint>

#include <immintrin.h>

#include "vlf/build/packed_ids.hpp"

namespace beamtrace::vlf {

#if defined(__AVX512BW__)
[[gnu::always_inline]] inline __m512i load_packed_ids(PackedIds ids, __mmask16 live) {
    if (live == 0) return _mm512_setzero_si512();
    const unsigned lo = unsigned(__builtin_ctz(live)), hi = 32u - unsigned(__builtin_clz(unsigned(live)));
    const __mmask64 bytes = ((std::uint64_t(1) << (3 * hi)) - 1u) & ~((std::uint64_t(1) << (3 * lo)) - 1u);
    const __m512i raw = _mm512_maskz_loadu_epi8(bytes, ids.bytes);
    const __m512i dwords = _mm512_permutexvar_epi32(
        _mm512_setr_epi32(0, 1, 2, 2, 3, 4, 5, 5, 6, 7, 8, 8, 9, 10, 11, 11), raw);
    const __m512i spread = _mm512_set4_epi32(int(0xFF0B0A09u), int(0xFF080706u), int(0xFF050403u), int(0xFF020100u));
    return _mm512_maskz_mov_epi32(live, _mm512_shuffle_epi8(dwords, spread));
}
#endif

}  // namespace beamtrace::vlf
