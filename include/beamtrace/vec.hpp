#pragma once
// Small value types shared by every public header: a 3-vector and an axis-aligned box.
#include <algorithm>
#include <cmath>
#include <limits>

namespace beamtrace {

struct Float3 {
    float x = 0, y = 0, z = 0;

    constexpr float operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
    constexpr float& operator[](int axis) { return axis == 0 ? x : (axis == 1 ? y : z); }
    friend constexpr Float3 operator+(Float3 a, Float3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend constexpr Float3 operator-(Float3 a, Float3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend constexpr Float3 operator*(Float3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
    friend constexpr Float3 operator*(float s, Float3 a) { return a * s; }
    friend constexpr bool operator==(Float3 a, Float3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
};

constexpr float dot(Float3 a, Float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Float3 cross(Float3 a, Float3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Float3 a) { return std::sqrt(dot(a, a)); }
inline Float3 normalize(Float3 a) { return a * (1.0f / length(a)); }
constexpr Float3 min(Float3 a, Float3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
constexpr Float3 max(Float3 a, Float3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }

// Axis-aligned box; a default box is empty (lower > upper) and grows by extend().
struct Box {
    Float3 lower{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                 std::numeric_limits<float>::infinity()};
    Float3 upper{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                 -std::numeric_limits<float>::infinity()};

    constexpr void extend(Float3 p) {
        lower = min(lower, p);
        upper = max(upper, p);
    }
    constexpr void extend(const Box& b) {
        lower = min(lower, b.lower);
        upper = max(upper, b.upper);
    }
    constexpr bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
    // p on or inside the box (false for an empty box and for NaN coordinates).
    constexpr bool contains(Float3 p) const {
        return lower.x <= p.x && p.x <= upper.x && lower.y <= p.y && p.y <= upper.y && lower.z <= p.z &&
               p.z <= upper.z;
    }
    // b within the box, faces included (true for an empty b inside, whatever its inverted corners).
    constexpr bool contains(const Box& b) const {
        return lower.x <= b.lower.x && lower.y <= b.lower.y && lower.z <= b.lower.z && upper.x >= b.upper.x &&
               upper.y >= b.upper.y && upper.z >= b.upper.z;
    }
    constexpr Float3 extent() const { return upper - lower; }
    constexpr Float3 center() const { return (lower + upper) * 0.5f; }
    inline float diagonal() const { return empty() ? 0.0f : length(extent()); }
    constexpr float surface_area() const {
        if (empty()) return 0.0f;
        const Float3 e = extent();
        return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
    constexpr float volume() const {
        if (empty()) return 0.0f;
        const Float3 e = extent();
        return e.x * e.y * e.z;
    }
};

}  // namespace beamtrace
