#pragma once
// Colours for false-colour images: a perceptual heat map for scalar values (depth, traversal
// steps) and the usual normal-to-colour mapping.
#include <cmath>
#include <cstdint>

#include "beamtrace/vec.hpp"

namespace beamtrace::report {

struct Rgb8 {
    std::uint8_t r = 0, g = 0, b = 0;
    friend constexpr bool operator==(Rgb8 a, Rgb8 b) { return a.r == b.r && a.g == b.g && a.b == b.b; }
};

// A viridis-like ramp from dark purple through blue and green to yellow, with lightness rising
// steadily, so it reads the same in grey. x is clamped to [0, 1]; NaN maps to 0. Linear
// interpolation between nine hand-picked stops.
inline Rgb8 heat_color(double x) {
    static constexpr std::uint8_t kStops[9][3] = {
        {68, 1, 84},    {72, 40, 120},  {62, 74, 137},  {49, 104, 142}, {38, 130, 142},
        {31, 158, 137}, {53, 183, 121}, {109, 205, 89}, {253, 231, 37},
    };
    if (!(x > 0.0)) x = 0.0;  // also catches NaN
    if (x > 1.0) x = 1.0;
    const double pos = x * 8.0;
    const int i = pos >= 8.0 ? 7 : static_cast<int>(pos);
    const double f = pos - i;
    auto mix = [&](int c) {
        return static_cast<std::uint8_t>(std::lround(kStops[i][c] + f * (kStops[i + 1][c] - kStops[i][c])));
    };
    return {mix(0), mix(1), mix(2)};
}

// value in [lo, hi] through the heat map (lo when hi <= lo).
inline Rgb8 heat_color(double value, double lo, double hi) {
    return heat_color(hi > lo ? (value - lo) / (hi - lo) : 0.0);
}

// A normal n (any length) as colour: each component of n / |n| from [-1, 1] to [0, 255].
// The zero vector and non-finite normals give mid grey.
inline Rgb8 normal_color(Float3 n) {
    const double len = std::sqrt(double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z);
    if (!(len > 0.0) || !std::isfinite(len)) return {128, 128, 128};
    auto channel = [&](float c) { return static_cast<std::uint8_t>(std::lround((c / len * 0.5 + 0.5) * 255.0)); };
    return {channel(n.x), channel(n.y), channel(n.z)};
}

}  // namespace beamtrace::report
