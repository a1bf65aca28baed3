#pragma once
// Double-precision vectors for the hierarchy's bounds. Float inputs (corners, ray components) are
// exact in double, and every bound is computed in double, then rounded so that it still contains
// what it bounds: the rounding of the float world never decides what is culled.
#include <cmath>
#include <limits>

#include "beamtrace/vec.hpp"

namespace beamtrace::crsh {

struct Vec3d {
    double x = 0, y = 0, z = 0;

    Vec3d() = default;
    constexpr Vec3d(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
    explicit constexpr Vec3d(Float3 f) : x(f.x), y(f.y), z(f.z) {}

    friend constexpr Vec3d operator+(Vec3d a, Vec3d b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend constexpr Vec3d operator-(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend constexpr Vec3d operator*(Vec3d a, double s) { return {a.x * s, a.y * s, a.z * s}; }
    friend constexpr Vec3d operator*(double s, Vec3d a) { return a * s; }
};

constexpr double dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3d cross(Vec3d a, Vec3d b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(Vec3d a) { return std::sqrt(dot(a, a)); }
inline double norm1(Vec3d a) { return std::fabs(a.x) + std::fabs(a.y) + std::fabs(a.z); }
// a / |a|; a must not be zero.
inline Vec3d unit(Vec3d a) { return a * (1.0 / length(a)); }
// The angle between two unit vectors, accurate at 0 and pi (atan2 of sine and cosine, not acos).
inline double angle_between(Vec3d a, Vec3d b) { return std::atan2(length(cross(a, b)), dot(a, b)); }

// The smallest float >= x (x finite and within float's range).
inline float round_up(double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}

}  // namespace beamtrace::crsh
