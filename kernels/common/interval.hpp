#pragma once
// Float intervals for beam bounds, widened outwards so that rounding can never make a bound
// exclude a ray it should contain (culling decisions built on them stay conservative).
#include <algorithm>
#include <cmath>

namespace beamtrace {

struct Interval {
    float lo, hi;
};

// Relative widening applied to every derived bound (a few thousand ulps: generous, cheap).
inline constexpr float kRelativePad = 1.0f / 65536.0f;

// lo - (|lo| R + pad) and hi + (|hi| R + pad): one rounding order, which the 4-wide SSE form of the
// inverse culling (split_rectangle.hpp) repeats lane by lane.
inline Interval widen(Interval a, float absolute_pad) {
    return {a.lo - (std::fabs(a.lo) * kRelativePad + absolute_pad),
            a.hi + (std::fabs(a.hi) * kRelativePad + absolute_pad)};
}

inline Interval operator+(Interval a, Interval b) { return {a.lo + b.lo, a.hi + b.hi}; }

inline Interval operator*(Interval a, Interval b) {
    const float p0 = a.lo * b.lo, p1 = a.lo * b.hi, p2 = a.hi * b.lo, p3 = a.hi * b.hi;
    return {std::min(std::min(p0, p1), std::min(p2, p3)), std::max(std::max(p0, p1), std::max(p2, p3))};
}

inline Interval hull(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)}; }

}  // namespace beamtrace
