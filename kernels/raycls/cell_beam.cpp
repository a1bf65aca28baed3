// The half-spaces of a ray-space cell's beam (cell_beam.hpp).
#include "raycls/cell_beam.hpp"

namespace beamtrace::raycls {

namespace {

void add(CellBeam& beam, const double n[3], double c) {
    HalfSpace& h = beam.planes[beam.count++];
    h.n[0] = n[0];
    h.n[1] = n[1];
    h.n[2] = n[2];
    h.c = c;
}

// The bounds of x_j (j = a or b, direction coordinate range [w0, w1]) over the beam: lower and upper
// half-spaces, one or two each.
void add_side(CellBeam& beam, int k, double s, int j, double lo, double hi, double w0, double w1, double s0,
              double s1) {
    double n[3] = {0, 0, 0};
    // Lower: x_j >= lo + min(w lambda).
    if (w0 >= 0.0) {
        n[j] = 1.0;
        add(beam, n, lo);  // lambda may be 0
        n[k] = -w0 * s;    // x_j - w0 (s x_k - s1) >= lo
        add(beam, n, lo - w0 * s1);
    } else {
        n[j] = 1.0;
        n[k] = -w0 * s;  // x_j - w0 (s x_k - s0) >= lo
        add(beam, n, lo - w0 * s0);
    }
    n[0] = n[1] = n[2] = 0.0;
    // Upper: x_j <= hi + max(w lambda).
    if (w1 <= 0.0) {
        n[j] = -1.0;
        add(beam, n, -hi);
        n[k] = w1 * s;  // -x_j + w1 (s x_k - s1) >= -hi
        add(beam, n, -hi + w1 * s1);
    } else {
        n[j] = -1.0;
        n[k] = w1 * s;  // -x_j + w1 (s x_k - s0) >= -hi
        add(beam, n, -hi + w1 * s0);
    }
}

}  // namespace

CellBeam make_cell_beam(const CellBounds& cell, double origin_margin, double direction_margin) {
    CellBeam beam;
    const int k = face_axis(cell.face), a = face_a(cell.face), b = face_b(cell.face);
    const double s = face_sign(cell.face);
    double lo[3], hi[3];
    for (int i = 0; i < 3; ++i) {
        lo[i] = double(cell.lo[i]) - origin_margin;
        hi[i] = double(cell.hi[i]) + origin_margin;
    }
    // min and max of s o_k over the box.
    const double s0 = s > 0 ? lo[k] : -hi[k];
    const double s1 = s > 0 ? hi[k] : -lo[k];
    double n[3] = {0, 0, 0};
    n[k] = s;
    add(beam, n, s0);
    add_side(beam, k, s, a, lo[a], hi[a], double(cell.u0) - direction_margin, double(cell.u1) + direction_margin, s0,
             s1);
    add_side(beam, k, s, b, lo[b], hi[b], double(cell.v0) - direction_margin, double(cell.v1) + direction_margin, s0,
             s1);
    return beam;
}

BoxSide box_side(const CellBeam& beam, const Box& box) {
    bool inside = true;
    for (int i = 0; i < beam.count; ++i) {
        const HalfSpace& h = beam.planes[i];
        double most = 0.0, least = 0.0;
        for (int j = 0; j < 3; ++j) {
            const double lo = h.n[j] * double(box.lower[j]), hi = h.n[j] * double(box.upper[j]);
            most += lo > hi ? lo : hi;
            least += lo < hi ? lo : hi;
        }
        if (most < h.c) return BoxSide::outside;
        inside = inside && least >= h.c;
    }
    return inside ? BoxSide::inside : BoxSide::partly;
}

bool may_meet_triangle(const CellBeam& beam, const Triangle& tri) {
    for (int i = 0; i < beam.count; ++i) {
        const HalfSpace& h = beam.planes[i];
        const double d0 = h.n[0] * double(tri.v0.x) + h.n[1] * double(tri.v0.y) + h.n[2] * double(tri.v0.z);
        const double d1 = h.n[0] * double(tri.v1.x) + h.n[1] * double(tri.v1.y) + h.n[2] * double(tri.v1.z);
        const double d2 = h.n[0] * double(tri.v2.x) + h.n[1] * double(tri.v2.y) + h.n[2] * double(tri.v2.z);
        if (d0 < h.c && d1 < h.c && d2 < h.c) return false;
    }
    return true;
}

}  // namespace beamtrace::raycls
