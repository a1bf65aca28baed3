#pragma once
// The beam of a ray-space cell: every point o + lambda * w with o in the cell's origin box, w a
// direction of its face rectangle and lambda >= 0. Arvo and Kirk bound it by planes; here it is the
// intersection of at most nine half-spaces n . x >= c, exact for a box swept along a rectangle of
// directions up to the extra facets of the sum (which only make the test keep more):
//   s x_k >= min(s o_k)                                    (the beam runs forwards along the face)
//   x_a >= lo_a + min(u lambda),  x_a <= hi_a + max(u lambda)   over u in [u0, u1], lambda in
//   [max(0, s x_k - max(s o_k)), s x_k - min(s o_k)], each one or two half-spaces; the same for b, v.
// Computed in double from the cell's float bounds grown by margins, so that rays classified into the
// cell by float comparisons, from float points, stay inside (docs/raycls.md).
#include "beamtrace/scene.hpp"
#include "raycls/ray_space.hpp"

namespace beamtrace::raycls {

struct HalfSpace {
    double n[3];
    double c;
};

struct CellBeam {
    HalfSpace planes[9];
    int count = 0;
};

// origin_margin: added on each side of the origin box; direction_margin: on each side of (u, v).
CellBeam make_cell_beam(const CellBounds& cell, double origin_margin, double direction_margin);

// False only when some half-space has every corner of the triangle strictly outside it.
bool may_meet_triangle(const CellBeam& beam, const Triangle& tri);
// Outside: some half-space has the whole box strictly outside it. Inside: the whole box lies in every
// half-space (every triangle in it may meet the beam; no test of its parts can drop anything).
enum class BoxSide { outside, partly, inside };
BoxSide box_side(const CellBeam& beam, const Box& box);

}  // namespace beamtrace::raycls
