#include "crsh/ray_keys.hpp"

#include <algorithm>
#include <cmath>

#include "common/morton.hpp"

namespace beamtrace::crsh {

namespace {

// [lo, lo + 2^bits) of f in [0, 1] (clamped; NaN gives 0).
std::uint32_t quantise(double f, int bits) {
    const double cells = std::ldexp(1.0, bits);
    const double q = std::floor(f * cells);
    if (!(q > 0.0)) return 0;
    return q >= cells ? static_cast<std::uint32_t>(cells) - 1u : static_cast<std::uint32_t>(q);
}

}  // namespace

BoundingRay bounding_ray(const Ray& r, CrshKey key) {
    const Vec3d org(r.org), dir(r.dir);
    const double length = std::isfinite(r.tfar) ? (static_cast<double>(r.tfar) - static_cast<double>(r.tnear)) *
                                                      crsh::length(dir) * (1.0 + 1e-12)
                                                : std::numeric_limits<double>::infinity();
    if (key == CrshKey::end_point && std::isfinite(r.tfar))
        return BoundingRay{org + dir * static_cast<double>(r.tfar), unit(dir) * -1.0, length};
    return BoundingRay{org + dir * static_cast<double>(r.tnear), unit(dir), length};
}

std::uint32_t direction_code(Vec3d d) {
    const double ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
    const int k = (ax > ay) ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
    const double c[3] = {d.x, d.y, d.z};
    const double m = std::fabs(c[k]);
    const std::uint32_t face = std::uint32_t(2 * k) + (c[k] < 0.0 ? 1u : 0u);
    const double u = c[(k + 1) % 3] / m, v = c[(k + 2) % 3] / m;  // in [-1, 1]
    const std::uint32_t qu = quantise((u + 1.0) * 0.5, kDirectionBits), qv = quantise((v + 1.0) * 0.5, kDirectionBits);
    return (face << (2 * kDirectionBits)) | (spread_bits_2(qu) << 1) | spread_bits_2(qv);
}

PositionCode::PositionCode(const Box& box, int bits) : bits_(bits) {
    lower_ = Vec3d(box.lower);
    const double e[3] = {double(box.upper.x) - double(box.lower.x), double(box.upper.y) - double(box.lower.y),
                         double(box.upper.z) - double(box.lower.z)};
    double s[3];
    for (int a = 0; a < 3; ++a) s[a] = e[a] > 0.0 && std::isfinite(e[a]) ? 1.0 / e[a] : 0.0;
    scale_ = Vec3d(s[0], s[1], s[2]);
}

std::uint32_t PositionCode::operator()(Vec3d p) const {
    if (bits_ == 0) return 0;
    const std::uint32_t qx = quantise((p.x - lower_.x) * scale_.x, bits_);
    const std::uint32_t qy = quantise((p.y - lower_.y) * scale_.y, bits_);
    const std::uint32_t qz = quantise((p.z - lower_.z) * scale_.z, bits_);
    return (spread_bits_3(qx) << 2) | (spread_bits_3(qy) << 1) | spread_bits_3(qz);
}

}  // namespace beamtrace::crsh
