#pragma once
// Lane masks of the library's baseline SSE code (four float lanes): a mask from four bits of a
// packet's lane word, and the four bits of a mask. Only for the units compiled for the baseline.
#include <cstdint>

#include <xsimd/xsimd.hpp>

namespace beamtrace::sse {

using Floats = xsimd::batch<float, xsimd::sse4_2>;
using Mask = xsimd::batch_bool<float, xsimd::sse4_2>;

// Lane i on when bit i of `four_bits` is set (higher bits ignored).
inline Mask lanes_on(std::uint32_t four_bits) {
    const __m128i bit = _mm_setr_epi32(1, 2, 4, 8);
    return _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(int(four_bits)), bit), bit));
}

inline std::uint32_t bits_of(const Mask& m) { return std::uint32_t(_mm_movemask_ps(m)); }

// std::min and std::max lane by lane: (y < x) ? y : x and (x < y) ? y : x, so that NaN operands and
// signed zeros come out as the scalar code's (the SIMD forms of scalar references stay bit for bit).
// MINPS a, b is (a < b) ? a : b and MAXPS a, b is (a > b) ? a : b, NaNs and signed zeros included,
// so with the operands swapped each is one instruction (a compare and a blend before).
inline Floats min_as_std(const Floats& x, const Floats& y) { return _mm_min_ps(y, x); }
inline Floats max_as_std(const Floats& x, const Floats& y) { return _mm_max_ps(y, x); }

// Horizontal minimum / maximum of the four lanes, in registers: min(min(a0, a1), min(a2, a3)) with
// std::min's rule for each pair, so the result is that scalar fold's, bit for bit.
inline float least(const Floats& v) {
    const Floats pairs = min_as_std(v, Floats(_mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1))));
    return _mm_cvtss_f32(min_as_std(pairs, Floats(_mm_shuffle_ps(pairs, pairs, _MM_SHUFFLE(1, 0, 3, 2)))));
}
inline float most(const Floats& v) {
    const Floats pairs = max_as_std(v, Floats(_mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1))));
    return _mm_cvtss_f32(max_as_std(pairs, Floats(_mm_shuffle_ps(pairs, pairs, _MM_SHUFFLE(1, 0, 3, 2)))));
}

}  // namespace beamtrace::sse
