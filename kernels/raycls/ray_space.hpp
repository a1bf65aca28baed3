#pragma once
// The 5D ray space of ray classification: a ray's origin point and its direction coded on the
// direction cube (face = dominant axis and its sign; u, v = the two other components over the
// dominant one's magnitude, in [-1, 1]), and the bounds of a cell of that space.
#include <cmath>
#include <cstdint>

#include "beamtrace/ray.hpp"

namespace beamtrace::raycls {

// Face f: axis f / 2, sign + when f is even. The face's other axes, in a fixed order: a = (k+1) % 3,
// b = (k+2) % 3.
inline int face_axis(int face) { return face >> 1; }
inline int face_sign(int face) { return (face & 1) ? -1 : 1; }
inline int face_a(int face) { return (face_axis(face) + 1) % 3; }
inline int face_b(int face) { return (face_axis(face) + 2) % 3; }

struct DirectionCode {
    int face = 0;
    float u = 0.0f, v = 0.0f;
};

// The dominant axis as the watertight test chooses it (ties go to the later axis of the pair the
// comparisons pick; any choice is exact: |u|, |v| <= 1 either way).
inline DirectionCode direction_code(const Float3& d) {
    const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
    const int k = (ax > ay) ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
    const float m = std::fabs(d[k]);
    DirectionCode c;
    c.face = 2 * k + (d[k] < 0.0f ? 1 : 0);
    c.u = d[(k + 1) % 3] / m;
    c.v = d[(k + 2) % 3] / m;
    return c;
}

// A cell: a box of origins, a face, a rectangle of (u, v). Halving at midpoints computed in float, so
// a point's child is decided by the same comparison that bounds the child.
struct CellBounds {
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    float u0 = -1.0f, u1 = 1.0f, v0 = -1.0f, v1 = 1.0f;
    int face = 0;
};

// Child `index` of a cell: bit 0 the upper half of u, bit 1 of v, and when the origins are split
// (`split_origins`), bits 2..4 the upper halves of x, y, z.
inline CellBounds child_bounds(const CellBounds& c, int index, bool split_origins) {
    CellBounds b = c;
    const float um = 0.5f * (c.u0 + c.u1), vm = 0.5f * (c.v0 + c.v1);
    if (index & 1) b.u0 = um; else b.u1 = um;
    if (index & 2) b.v0 = vm; else b.v1 = vm;
    if (split_origins)
        for (int k = 0; k < 3; ++k) {
            const float mid = 0.5f * (c.lo[k] + c.hi[k]);
            if (index & (4 << k)) b.lo[k] = mid; else b.hi[k] = mid;
        }
    return b;
}

// Which child of c holds the point p and the direction (u, v).
inline int child_index(const CellBounds& c, const float p[3], float u, float v, bool split_origins) {
    int index = (u >= 0.5f * (c.u0 + c.u1) ? 1 : 0) | (v >= 0.5f * (c.v0 + c.v1) ? 2 : 0);
    if (split_origins)
        for (int k = 0; k < 3; ++k)
            if (p[k] >= 0.5f * (c.lo[k] + c.hi[k])) index |= 4 << k;
    return index;
}

// Whether p and (u, v) lie in the closed cell c (a point on a shared bound may be in either cell:
// both candidate sets cover the closed cell, so either answers exactly).
inline bool cell_contains(const CellBounds& c, const float p[3], int face, float u, float v, bool check_origin) {
    if (face != c.face || u < c.u0 || u > c.u1 || v < c.v0 || v > c.v1) return false;
    if (check_origin)
        for (int k = 0; k < 3; ++k)
            if (p[k] < c.lo[k] || p[k] > c.hi[k]) return false;
    return true;
}

}  // namespace beamtrace::raycls
