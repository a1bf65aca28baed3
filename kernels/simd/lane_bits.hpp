#pragma once
// Bit i set for each true lane of an xsimd float mask (lane_bits), each lane's sign bit (sign_bits),
// and the mask of the lanes whose bit is set (lanes_on), for the widest instruction set the including
// unit is compiled for (and only that one: a unit compiled with -mavx2 must never provide the code a
// narrower unit links to). Included only by the per-ISA units.
//
// Mask operators: xsimd 8.1 (Debian 12) computes an AVX-512 batch_bool ^ batch_bool as |, and its
// SSE and AVX batch_bool != compares the masks' bit patterns as floats (all-ones is a NaN: always
// true); write an xor of masks as (a & ~b) | (~a & b) (stream/group_traversal_impl.hpp). &, | and ~
// are right on every width.
#include <cstdint>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

namespace beamtrace::simd {

template <class Arch>
std::uint32_t lane_bits(const xsimd::batch_bool<float, Arch>& m);
// Bit i set when lane i's sign bit is set (negative numbers, -0, NaNs with the sign bit).
template <class Arch>
std::uint32_t sign_bits(const xsimd::batch<float, Arch>& v);
// Lane i true when bit i of `bits` is set (bits above the register's lanes ignored).
template <class Arch>
xsimd::batch_bool<float, Arch> lanes_on(std::uint32_t bits);

#if defined(__AVX512BW__)
template <>
inline std::uint32_t lane_bits<xsimd::avx512bw>(const xsimd::batch_bool<float, xsimd::avx512bw>& m) {
    return std::uint32_t(static_cast<__mmask16>(m));
}
template <>
inline std::uint32_t sign_bits<xsimd::avx512bw>(const xsimd::batch<float, xsimd::avx512bw>& v) {
    return std::uint32_t(_mm512_movepi32_mask(_mm512_castps_si512(v)));
}
template <>
inline xsimd::batch_bool<float, xsimd::avx512bw> lanes_on<xsimd::avx512bw>(std::uint32_t bits) {
    return xsimd::batch_bool<float, xsimd::avx512bw>(__mmask16(bits & 0xFFFFu));
}
#elif defined(__AVX2__)
template <>
inline std::uint32_t lane_bits<xsimd::avx2>(const xsimd::batch_bool<float, xsimd::avx2>& m) {
    return std::uint32_t(_mm256_movemask_ps(m));
}
template <>
inline std::uint32_t sign_bits<xsimd::avx2>(const xsimd::batch<float, xsimd::avx2>& v) {
    return std::uint32_t(_mm256_movemask_ps(v));
}
template <>
inline xsimd::batch_bool<float, xsimd::avx2> lanes_on<xsimd::avx2>(std::uint32_t bits) {
    const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(bits)), bit), bit));
}
#elif defined(__SSE4_2__)
template <>
inline std::uint32_t lane_bits<xsimd::sse4_2>(const xsimd::batch_bool<float, xsimd::sse4_2>& m) {
    return std::uint32_t(_mm_movemask_ps(m));
}
template <>
inline std::uint32_t sign_bits<xsimd::sse4_2>(const xsimd::batch<float, xsimd::sse4_2>& v) {
    return std::uint32_t(_mm_movemask_ps(v));
}
template <>
inline xsimd::batch_bool<float, xsimd::sse4_2> lanes_on<xsimd::sse4_2>(std::uint32_t bits) {
    const __m128i bit = _mm_setr_epi32(1, 2, 4, 8);
    return _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(int(bits)), bit), bit));
}
#endif

}  // namespace beamtrace::simd
