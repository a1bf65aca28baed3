#include "mlrta/beam_triangles.hpp"

#include <cmath>

namespace beamtrace::mlrta {

OneOriginFrustum beam_frustum(const Beam& beam) {
    OneOriginFrustum f;
    if (beam.empty || !beam.coherent || !beam.one_origin) return f;
    f.m = beam.main_axis;
    f.j0 = f.m == 0 ? 1 : 0;
    f.j1 = f.m == 2 ? 1 : 2;
    f.sm = float(beam.sign[f.m]);
    f.origin = beam.origin;
    for (int j = 0; j < 3; ++j) {
        // slope[m][j] is the range of dir_j / dir_m; the frustum keeps dir_j / |dir_m|.
        const Interval s = beam.slope[f.m][j];
        f.slope[j] = f.sm > 0 ? s : Interval{-s.hi, -s.lo};
    }
    // The same widening as a packet's frustum (make_one_origin_frustum): the beam's ranges are already
    // outward-rounded, this adds room for the corners' own rounding.
    for (int j = 0; j < 3; ++j) {
        const float spread = (f.slope[j].hi - f.slope[j].lo) + std::fabs(f.slope[j].lo) + std::fabs(f.slope[j].hi);
        f.slope[j] = {f.slope[j].lo - spread * 1e-4f - 1e-6f, f.slope[j].hi + spread * 1e-4f + 1e-6f};
    }
    f.reach = beam.apex_far.hi * (1.0f + 1.0f / 65536.0f);
    f.valid = std::isfinite(f.slope[f.j0].lo) && std::isfinite(f.slope[f.j0].hi) && std::isfinite(f.slope[f.j1].lo) &&
              std::isfinite(f.slope[f.j1].hi);
    return f;
}

namespace {

struct D3 {
    double x[3];
    double operator[](int k) const { return x[k]; }
};

D3 sub(const D3& a, const D3& b) { return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}}; }
D3 cross(const D3& a, const D3& b) {
    return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}
double dot(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
D3 widen(Float3 p) { return {{double(p.x), double(p.y), double(p.z)}}; }

}  // namespace

BeamBlock beam_block(const Beam& beam, const OneOriginFrustum& f, const Triangle& tri, const Box& cell) {
    BeamBlock none;
    if (!f.valid || !beam.one_origin) return none;
    const D3 o = widen(f.origin);
    const D3 v[3] = {widen(tri.v0), widen(tri.v1), widen(tri.v2)};
    const D3 n = cross(sub(v[1], v[0]), sub(v[2], v[0]));
    const double nn = dot(n, n);
    if (!(nn > 0.0)) return none;
    double reach = 0.0;  // largest coordinate of a corner relative to the apex
    for (const D3& p : v)
        for (int k = 0; k < 3; ++k) reach = std::max(reach, std::fabs(p[k] - o[k]));
    // The four corner rays, directions scaled to |dir_main| = 1 (so t is the distance along the
    // main axis from the apex).
    D3 corner[4];
    double widest = 1.0;
    for (int c = 0; c < 4; ++c) {
        D3& d = corner[c];
        d.x[f.m] = f.sm;
        d.x[f.j0] = (c & 1) ? f.slope[f.j0].hi : f.slope[f.j0].lo;
        d.x[f.j1] = (c & 2) ? f.slope[f.j1].hi : f.slope[f.j1].lo;
        widest = std::max({widest, std::fabs(d[f.j0]), std::fabs(d[f.j1])});
    }
    // The single-precision test decides the sign of each edge function with an error of a few ulps
    // of the products of sheared coordinates (at most 2 * reach each); relative to the sum of the
    // edge functions (twice the area projected along the ray) that is at most about
    // 2^-17 reach^2 widest / |n.d| in barycentric terms. Demand 32 times that, for every corner.
    double margin = 0.0;
    for (const D3& d : corner) {
        const double nd = std::fabs(dot(n, d));
        if (!(nd > 0.0)) return none;
        margin = std::max(margin, std::ldexp(reach * reach * widest / nd, -12));
    }
    const double plane = dot(n, sub(v[0], o));
    BeamBlock out;
    out.inside = true;
    for (const D3& d : corner) {
        const double t = plane / dot(n, d);
        // In front of every start and before every end, with relative room for rounding.
        if (!(t > 0.0) || !(t * (1.0 - 1e-5) > double(beam.apex_near.hi)) ||
            !(t * (1.0 + 1e-5) < double(beam.apex_far.lo)))
            return none;
        const D3 p{{o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]}};
        for (int i = 0; i < 3; ++i) {
            const double lambda = dot(n, cross(sub(v[(i + 1) % 3], p), sub(v[(i + 2) % 3], p))) / nn;
            if (!(lambda >= margin)) return none;
        }
        out.far = std::max(out.far, t);
        for (int k = 0; k < 3; ++k) {
            const double lo = cell.lower[k], hi = cell.upper[k];
            const bool in =
                lo == hi ? std::fabs(p[k] - lo) <= 1e-9 * (std::fabs(lo) + reach) : p[k] >= lo && p[k] <= hi;
            out.inside = out.inside && in;
        }
    }
    out.blocks = true;
    return out;
}

}  // namespace beamtrace::mlrta
