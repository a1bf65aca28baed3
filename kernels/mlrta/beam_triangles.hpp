#pragma once
// A beam with one origin against single triangles (MLRTA section 4.1, "potential intersections" and
// termination (4), first case), used by the entry-point search:
//   - culling: no ray of the beam can meet a triangle that lies outside its frustum (the same test,
//     and the same kernels, as the packet frustum of interval traversal: kdtree/packet/one_origin_frustum.hpp);
//   - blocking: every ray of the beam meets one triangle inside a cell, before its segment ends;
//     then no ray of the beam goes beyond that cell, and the search may stop there.
// Both decisions are conservative: a triangle is culled only if no ray can hit it, and blocking is
// claimed only if every ray of the beam hits the triangle with room to spare for the rounding of
// the watertight test.
#include "beamtrace/scene.hpp"
#include "mlrta/beam.hpp"
#include "kdtree/packet/one_origin_frustum.hpp"

namespace beamtrace::mlrta {

using kdtree::OneOriginFrustum;

// The frustum of a beam with one origin (invalid otherwise, or for an incoherent beam): the beam's
// slope ranges along its main axis, widened as a packet's are.
OneOriginFrustum beam_frustum(const Beam& beam);

// Whether every ray of the beam (any direction in the frustum `f`, which must be beam_frustum(beam),
// any start and end in the beam's apex ranges) hits `tri` within its segment, how far along the main
// axis from the apex those hits lie at most, and whether they all lie inside `cell` (on its plane,
// for a flat cell). Computed in double for the four corner rays of the frustum: the hit points of
// all the beam's rays lie in the convex hull of theirs (the hit distance is largest at a corner),
// and the barycentric margin covers the rounding of the single-precision watertight test.
struct BeamBlock {
    bool blocks = false;  // every ray hits the triangle within its segment
    bool inside = false;  // ... at a point of `cell`
    double far = 0.0;     // the largest distance along the main axis from the apex of those hits
};
BeamBlock beam_block(const Beam& beam, const OneOriginFrustum& f, const Triangle& tri, const Box& cell);

}  // namespace beamtrace::mlrta
