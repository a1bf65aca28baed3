#pragma once
// The rays' side of CRSH: the half-line each ray is bounded by (where its segment starts, or for
// end-point keys where it ends, and its unit direction) and its key (the paper's hash): the bounding
// point quantised in the scene's box, in Morton order, above a direction code without the seam of
// spherical coordinates (cube face, then Morton order of the two face coordinates).
#include <cstdint>
#include <limits>

#include "beamtrace/crsh.hpp"
#include "beamtrace/ray.hpp"
#include "crsh/vec3d.hpp"

namespace beamtrace::crsh {

// Every point of the ray's segment is start + s * dir for some s >= 0 (dir unit, start computed in
// double: org + tnear * dir, or org + tfar * dir with dir reversed for CrshKey::end_point when tfar
// is finite). The ray must describe a segment. length: how far the segment runs from start (in the
// units of the unit dir, rounded up), infinite for an infinite tfar.
struct BoundingRay {
    Vec3d start;
    Vec3d dir;
    double length = std::numeric_limits<double>::infinity();
};
BoundingRay bounding_ray(const Ray& ray, CrshKey key);

inline constexpr int kDirectionBits = 14;  // per face coordinate
// 3 bits of cube face (2 k + 1 for a negative dominant component k; ties between components as in the
// watertight test's choice of axis), then the Morton interleave of the two other components over the
// dominant one's magnitude, each quantised to kDirectionBits in [-1, 1]: 31 bits.
std::uint32_t direction_code(Vec3d unit_dir);

// Quantises points of a box (grown to cover degenerate extents) to `bits` per axis, in Morton order.
class PositionCode {
public:
    PositionCode(const Box& box, int bits);
    std::uint32_t operator()(Vec3d p) const;

private:
    Vec3d lower_, scale_;
    int bits_;
};

// (position code << 31) | direction code.
inline std::uint64_t ray_key(const BoundingRay& b, const PositionCode& position) {
    return (std::uint64_t{position(b.start)} << 31) | direction_code(b.dir);
}

}  // namespace beamtrace::crsh
