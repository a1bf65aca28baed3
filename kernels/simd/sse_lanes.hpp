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

}  // namespace beamtrace::sse
