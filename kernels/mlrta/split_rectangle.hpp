#pragma once
// The beam's rectangle on a split plane (condition (3) of MLRTA section 4.1), the quantity of
// inverse frustum culling at inner nodes, computed 4-wide with SSE as in the paper: one register
// holds [lo_j, hi_j, lo_l, hi_l] for the two axes j, l other than the plane's axis k. Interval
// products take their minima and maxima across lane pairs; every widening has the scalar form's
// rounding order, so the rectangle is plane_range's for j and l, bit for bit (the reference,
// split_rectangle_reference, is tested against it). Only SSE2 operations, which every x86-64 has,
// so this needs no run-time dispatch; wider registers do not pay for one plane at a time.
#include <immintrin.h>

#include "mlrta/beam.hpp"

namespace beamtrace::mlrta {

// The axes the rectangle's lanes describe: j = (k + 1) % 3 in lanes 0-1, l = (k + 2) % 3 in 2-3.
inline int rectangle_axis(int k, int pair) { return (k + 1 + pair) % 3; }

// Scalar reference: plane_range(k, p, j) and plane_range(k, p, l).
inline void split_rectangle_reference(const Beam& beam, int k, float p, float out[4]) {
    for (int pair = 0; pair < 2; ++pair) {
        const Interval r = beam.plane_range(k, p, rectangle_axis(k, pair));
        out[2 * pair] = r.lo;
        out[2 * pair + 1] = r.hi;
    }
}

inline __m128 split_rectangle(const Beam& beam, int k, float p) {
    const int j = rectangle_axis(k, 0), l = rectangle_axis(k, 1);
    const __m128 rel = _mm_set1_ps(kRelativePad), pad = _mm_set1_ps(beam.pad);
    const __m128 sign = _mm_setr_ps(-1.0f, 1.0f, -1.0f, 1.0f);  // lower bounds go down, upper up
    const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
    auto widen4 = [&](__m128 x) {
        return _mm_add_ps(x, _mm_mul_ps(sign, _mm_add_ps(_mm_mul_ps(_mm_and_ps(x, abs_mask), rel), pad)));
    };
    // The offset interval [p - starts.upper[k], p - starts.lower[k]], widened (lanes: lo, hi, lo, hi).
    const __m128 offset = widen4(_mm_sub_ps(_mm_set1_ps(p), _mm_setr_ps(beam.starts.upper[k], beam.starts.lower[k],
                                                                        beam.starts.upper[k], beam.starts.lower[k])));
    // offset * slope for both axes: products of either offset bound with the slope bounds
    // [s_lo, s_hi] of j and of l; the interval's ends are the minimum and maximum of each four.
    const __m128 slope =
        _mm_setr_ps(beam.slope[k][j].lo, beam.slope[k][j].hi, beam.slope[k][l].lo, beam.slope[k][l].hi);
    const __m128 a = _mm_mul_ps(_mm_shuffle_ps(offset, offset, _MM_SHUFFLE(0, 0, 0, 0)), slope);
    const __m128 b = _mm_mul_ps(_mm_shuffle_ps(offset, offset, _MM_SHUFFLE(1, 1, 1, 1)), slope);
    // std::min / std::max order: min(x, y) is (y < x) ? y : x, max(x, y) is (x < y) ? y : x
    // (SSE2 selects: the header is also compiled into units without SSE4).
    auto select = [](__m128 mask, __m128 yes, __m128 no) {
        return _mm_or_ps(_mm_and_ps(mask, yes), _mm_andnot_ps(mask, no));
    };
    auto min4 = [&](__m128 x, __m128 y) { return select(_mm_cmplt_ps(y, x), y, x); };
    auto max4 = [&](__m128 x, __m128 y) { return select(_mm_cmplt_ps(x, y), y, x); };
    // Interval::operator*: min(min(p0, p1), min(p2, p3)) with p0 = lo*lo, p1 = lo*hi, p2 = hi*lo,
    // p3 = hi*hi; here a = (p0, p1) and b = (p2, p3) for each axis.
    const __m128 a_swap = _mm_shuffle_ps(a, a, _MM_SHUFFLE(2, 3, 0, 1)),
                 b_swap = _mm_shuffle_ps(b, b, _MM_SHUFFLE(2, 3, 0, 1));
    const __m128 lo = min4(min4(a, a_swap), min4(b, b_swap));  // valid in lanes 0 and 2
    const __m128 hi = max4(max4(a_swap, a), max4(b_swap, b));  // valid in lanes 1 and 3
    const __m128 along = widen4(select(_mm_castsi128_ps(_mm_setr_epi32(0, -1, 0, -1)), hi, lo));
    const __m128 starts =
        _mm_setr_ps(beam.starts.lower[j], beam.starts.upper[j], beam.starts.lower[l], beam.starts.upper[l]);
    return widen4(_mm_add_ps(starts, along));
}

}  // namespace beamtrace::mlrta
