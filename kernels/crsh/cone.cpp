#include "crsh/cone.hpp"

#include <algorithm>
#include <cmath>

namespace beamtrace::crsh {

void grow_cone(Cone& cone, Vec3d r) {
    if (cone.spread >= kPi) return;
    const double angle = angle_between(cone.axis, r);
    if (angle <= cone.spread) return;
    if (angle + cone.spread >= kPi) {
        cone.spread = kPi;
        return;
    }
    const Vec3d x = cone.axis;
    const Vec3d across = x * dot(x, r) - r;
    const double across_length = length(across);
    if (!(across_length > 0.0)) {  // r parallel to x yet outside the cone: rounding; the whole sphere
        cone.spread = kPi;
        return;
    }
    const Vec3d q = across * (1.0 / across_length);
    const Vec3d e = x * std::cos(cone.spread) + q * std::sin(cone.spread);
    const Vec3d bisector = e + r;
    const double bisector_length = length(bisector);
    if (!(bisector_length > 0.0)) {
        cone.spread = kPi;
        return;
    }
    cone.axis = bisector * (1.0 / bisector_length);
    // Both angles are half the angle from e to r; the larger keeps both ends inside after rounding.
    cone.spread = std::min(kPi, std::max(angle_between(cone.axis, r), angle_between(cone.axis, e)));
}

Cone grow_cone(std::span<const Vec3d> directions) {
    Cone cone = cone_of(directions.front());
    for (std::size_t i = 1; i < directions.size(); ++i) grow_cone(cone, directions[i]);
    return cone;
}

double largest_angle(Vec3d axis, std::span<const Vec3d> directions) {
    double a = 0.0;
    for (const Vec3d& d : directions) a = std::max(a, angle_between(axis, d));
    return a;
}

Cone merge_cones(std::span<const Cone> children) {
    Vec3d sum{0, 0, 0};
    for (const Cone& c : children) {
        if (c.spread >= kPi) return Cone{c.axis, kPi};
        sum = sum + c.axis;
    }
    const double sum_length = length(sum);
    // Axes that (nearly) cancel out give no direction worth trusting.
    if (!(sum_length > 1e-9 * static_cast<double>(children.size()))) return Cone{children.front().axis, kPi};
    Cone merged{sum * (1.0 / sum_length), 0.0};
    for (const Cone& c : children)
        merged.spread = std::max(merged.spread, angle_between(merged.axis, c.axis) + c.spread);
    merged.spread = std::min(merged.spread, kPi);
    return merged;
}

}  // namespace beamtrace::crsh
