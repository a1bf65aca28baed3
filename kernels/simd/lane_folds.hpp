#pragma once
// std::min / std::max lane by lane, and folds over a packet's 16 lanes in the order of the library's
// SSE reference code, for any register width. Included only by the per-ISA units; everything here
// has internal linkage or is a template of the unit's own Arch, so no copy compiled for a wider
// instruction set can be linked into a narrower unit.
//
// The order matters only for ties: std::min and std::max keep the first of equal values (+0 and -0
// compare equal) and ignore a NaN that comes second. The SSE references (packet_lanes.cpp, lane_range)
// keep four accumulators, accumulator j folding lanes j, j + 4, j + 8, j + 12 in that order, then
// combine them as (a0, a1) and (a2, a3) (sse::least / sse::most). A fold here takes a wider
// register's lanes to the same four accumulators four at a time, in lane order, and ends with the
// same combination: the same float, bit for bit.
#include <cstdint>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

#include "beamtrace/ray.hpp"

namespace beamtrace::simd {
namespace {

// std::min(x, y) = (y < x) ? y : x and std::max(x, y) = (x < y) ? y : x, lane by lane: xsimd's min
// and max are MINPS / MAXPS (a < b ? a : b, a > b ? a : b, the second operand on ties and NaNs) at
// every width, so with the operands swapped they are std's.
template <class B>
B min_as_std(const B& x, const B& y) {
    return xsimd::min(y, x);
}
template <class B>
B max_as_std(const B& x, const B& y) {
    return xsimd::max(y, x);
}

// Four lanes i .. i + 3 of a register as an SSE register.
template <int kQuarter>
__m128 quarter(__m128 v) {
    static_assert(kQuarter == 0);
    return v;
}
#if defined(__AVX2__)
template <int kQuarter>
__m128 quarter(__m256 v) {
    static_assert(kQuarter < 2);
    if constexpr (kQuarter == 0) return _mm256_castps256_ps128(v);
    else return _mm256_extractf128_ps(v, 1);
}
#endif
#if defined(__AVX512F__)
template <int kQuarter>
__m128 quarter(__m512 v) {
    static_assert(kQuarter < 4);
    return _mm512_extractf32x4_ps(v, kQuarter);
}
#endif

// The four accumulators of a std::min fold (kMax false) or a std::max fold (kMax true), starting at
// +infinity and -infinity.
template <bool kMax>
struct LaneFold {
    __m128 acc = _mm_set1_ps(kMax ? -kInfinity : kInfinity);

    void add4(__m128 x) { acc = kMax ? _mm_max_ps(x, acc) : _mm_min_ps(x, acc); }  // std::max / min(acc, x)
    // A register's lanes, four at a time in lane order.
    template <class B>
    void add(const B& v) {
        constexpr int kQuarters = int(B::size) / 4;
        const auto reg = typename B::register_type(v);
        add4(quarter<0>(reg));
        if constexpr (kQuarters > 1) add4(quarter<1>(reg));
        if constexpr (kQuarters > 2) {
            add4(quarter<2>(reg));
            add4(quarter<3>(reg));
        }
    }
    // The lanes of `on`, others left out (the fold of +-infinity in their place: the same result).
    template <class B, class M>
    void add(const B& v, const M& on) {
        add(xsimd::select(on, v, B(kMax ? -kInfinity : kInfinity)));
    }
    // sse::least / sse::most: (a0 with a1) with (a2 with a3).
    float result() const {
        auto pick = [](__m128 x, __m128 y) { return kMax ? _mm_max_ps(y, x) : _mm_min_ps(y, x); };  // std's (x, y)
        const __m128 pairs = pick(acc, _mm_shuffle_ps(acc, acc, _MM_SHUFFLE(2, 3, 0, 1)));
        return _mm_cvtss_f32(pick(pairs, _mm_shuffle_ps(pairs, pairs, _MM_SHUFFLE(1, 0, 3, 2))));
    }
};
using MinFold = LaneFold<false>;
using MaxFold = LaneFold<true>;

}  // namespace
}  // namespace beamtrace::simd
