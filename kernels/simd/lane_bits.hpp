#pragma once
// Bit i set for each true lane of an xsimd float mask, for the widest instruction set the including
// unit is compiled for (and only that one: a unit compiled with -mavx2 must never provide the code a
// narrower unit links to). Included only by the per-ISA units.
#include <cstdint>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

namespace beamtrace::simd {

template <class Arch>
std::uint32_t lane_bits(const xsimd::batch_bool<float, Arch>& m);

#if defined(__AVX512BW__)
template <>
inline std::uint32_t lane_bits<xsimd::avx512bw>(const xsimd::batch_bool<float, xsimd::avx512bw>& m) {
    return std::uint32_t(static_cast<__mmask16>(m));
}
#elif defined(__AVX2__)
template <>
inline std::uint32_t lane_bits<xsimd::avx2>(const xsimd::batch_bool<float, xsimd::avx2>& m) {
    return std::uint32_t(_mm256_movemask_ps(m));
}
#elif defined(__SSE4_2__)
template <>
inline std::uint32_t lane_bits<xsimd::sse4_2>(const xsimd::batch_bool<float, xsimd::sse4_2>& m) {
    return std::uint32_t(_mm_movemask_ps(m));
}
#endif

}  // namespace beamtrace::simd
