#pragma once
// The direct frustum test of Assarsson and Moller, as described in MLRTA section 3.3 (kept as an
// option to measure the paper's claim that the inverse test needs fewer entry-point steps): four
// planes through the beam's common origin bound its rays; a box is outside when its n-vertex lies
// outside one plane. Only for beams with one start point.
#include <cmath>

#include "mlrta/beam.hpp"

namespace beamtrace::mlrta {

struct Frustum4 {
    Float3 origin;
    Float3 normal[4];  // outward normals: inside means dot(normal, x - origin) <= 0
    float pad = 0.0f;
    bool valid = false;
};

inline Frustum4 make_frustum(const Beam& beam) {
    Frustum4 f;
    if (!beam.coherent || !(beam.starts.lower == beam.starts.upper)) return f;
    f.origin = beam.starts.lower;
    const int m = beam.main_axis;
    const float sm = float(beam.sign[m]);
    int n = 0;
    for (int j = 0; j < 3; ++j) {
        if (j == m) continue;
        // Inside: lo * w <= u_j <= hi * w, with w = u_m * sm and the ratio dir_j / |dir_m| in [lo, hi].
        const Interval s = beam.slope[m][j];
        const float lo = sm > 0 ? s.lo : -s.hi, hi = sm > 0 ? s.hi : -s.lo;
        Float3 a{}, b{};
        a[j] = 1.0f;
        a[m] = -hi * sm;  // u_j - hi * w <= 0
        b[j] = -1.0f;
        b[m] = lo * sm;  // lo * w - u_j <= 0
        f.normal[n++] = a;
        f.normal[n++] = b;
    }
    f.pad = beam.pad;
    f.valid = true;
    return f;
}

// True if the box is certainly outside the frustum (n-vertex test, 6 multiplies and 5 adds per
// plane group in the paper's SIMD form; written per plane here).
inline bool frustum_misses_box(const Frustum4& f, const Box& box) {
    for (const Float3& n : f.normal) {
        float value = 0.0f, scale = 0.0f;
        for (int c = 0; c < 3; ++c) {
            const float v = (n[c] > 0.0f ? box.lower[c] : box.upper[c]) - f.origin[c];
            value += n[c] * v;
            scale += std::fabs(n[c] * v);
        }
        if (value > scale * kRelativePad + f.pad) return true;
    }
    return false;
}

}  // namespace beamtrace::mlrta
