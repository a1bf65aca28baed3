#include "oracle/embree_segment.hpp"

#include <algorithm>
#include <cmath>

namespace beamtrace::oracle {

namespace {

// Embree asserts (ray.valid()) that no origin or direction component exceeds FLT_LARGE = 1.844e18
// in magnitude; larger values abort the process.
constexpr float kEmbreeLargest = 1.844e18f;
// Directions are scaled by a power of two to at most this (exact, t is scaled back).
constexpr float kLargestDirection = 1.152921504606846976e18f;  // 2^60

bool finite(Float3 p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }
float largest(Float3 p) { return std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}); }

}  // namespace

std::optional<EmbreeSegment> to_embree(const Ray& r) {
    if (!finite(r.org) || !finite(r.dir)) return std::nullopt;
    if (r.dir.x == 0.0f && r.dir.y == 0.0f && r.dir.z == 0.0f) return std::nullopt;
    if (std::isnan(r.tnear) || std::isnan(r.tfar) || !std::isfinite(r.tnear)) return std::nullopt;
    if (!(r.tnear <= r.tfar)) return std::nullopt;
    EmbreeSegment s{r.org, r.dir, r.tnear, r.tfar, 0.0f};
    if (r.tnear < 0.0f) {
        const double tn = r.tnear;
        s.org = Float3{float(r.org.x + tn * r.dir.x), float(r.org.y + tn * r.dir.y), float(r.org.z + tn * r.dir.z)};
        if (!finite(s.org)) return std::nullopt;
        s.tnear = 0.0f;
        s.tfar = std::isinf(r.tfar) ? r.tfar : float(double(r.tfar) - tn);
        s.shift = r.tnear;
    }
    // Beyond Embree's range: an origin cannot be moved there without changing the ray, so such rays
    // report no hit; a direction is scaled down by a power of two (t scaled up, exactly).
    if (largest(s.org) > kEmbreeLargest) return std::nullopt;
    if (largest(s.dir) > kLargestDirection) {
        int exponent = 0;
        std::frexp(largest(s.dir) / kLargestDirection, &exponent);
        s.t_scale = std::ldexp(1.0f, exponent);
        s.dir = s.dir * (1.0f / s.t_scale);
        s.tnear = s.tnear * s.t_scale;
        s.tfar = s.tfar * s.t_scale;
    }
    return s;
}

}  // namespace beamtrace::oracle
