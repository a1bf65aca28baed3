#pragma once
// Cones of directions: a unit axis and a half-angle (the spread). Level-1 nodes grow theirs ray by
// ray with Szecsi's compact-cone formulas (CRSH eqs. 1-4), upper levels merge their children's.
// A cone of spread pi/2 or more is "wide": the sphere-cone test accepts everything for it.
#include <numbers>
#include <span>

#include "crsh/vec3d.hpp"

namespace beamtrace::crsh {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kHalfPi = std::numbers::pi / 2;

struct Cone {
    Vec3d axis{0, 0, 1};  // unit
    double spread = 0.0;  // half-angle in radians, 0..pi

    bool wide() const { return spread >= kHalfPi; }
};

// The cone of one unit direction (spread 0).
inline Cone cone_of(Vec3d direction) { return Cone{direction, 0.0}; }

// Szecsi's step: the smallest cone holding the cone and the unit direction r. With the guards of the
// notes: r within the cone (angle <= spread, "<=" so identical directions change nothing) leaves it
// alone; angles come from atan2 (no acos of a dot product rounded past 1); r opposite the cone's far
// edge (angle + spread >= pi, antiparallel directions among them) makes the whole sphere (spread pi)
// instead of normalising a zero vector. Otherwise, x the axis, phi the spread:
//   q = normalise((x.r) x - r)      the unit vector across x pointing away from r
//   e = x cos(phi) + q sin(phi)     the cone's edge farthest from r
//   x' = normalise(e + r)           the new axis, halfway between e and r
//   phi' = angle(x', r)             half the angle from e to r
void grow_cone(Cone& cone, Vec3d r);

// Szecsi's cone of unit directions (the first one's cone grown by the others); `directions` not empty.
Cone grow_cone(std::span<const Vec3d> directions);

// The largest angle between the axis and a direction.
double largest_angle(Vec3d axis, std::span<const Vec3d> directions);

// A cone holding the children's cones (the notes' n-ary form of CRSH eq. 6): axis = normalise(sum of
// the children's axes), spread = max over children of (angle(axis, child axis) + child spread),
// capped at pi; the whole sphere when a child already is or the axes cancel out.
Cone merge_cones(std::span<const Cone> children);

}  // namespace beamtrace::crsh
