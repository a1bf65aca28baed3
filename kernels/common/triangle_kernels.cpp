// The scalar triangle kernels (the reference, lane by lane) and the run-time choice among the sets.
#include "common/triangle_kernels.hpp"

#include "common/triangle_reference.hpp"

namespace beamtrace {

namespace {

// Lane i of out: the reference's answer for the ray and the triangle.
void test_lane(const WatertightRay& r, const Triangle& tri, int i, LaneHits& out) {
    TriangleHit h;
    if (intersect_triangle(r, tri, h)) {
        out.t[i] = h.t;
        out.u[i] = h.u;
        out.v[i] = h.v;
        out.mask |= 1u << i;
    }
}

void scalar_ray_xn(const WatertightRay& r, const Triangle* const* tris, int n, LaneHits& out) {
    out.mask = 0;
    for (int i = 0; i < n; ++i) {
        test_lane(r, *tris[i], i, out);
    }
}

void scalar_ray_rows(const WatertightRay& r, const float* rows, std::size_t stride, std::size_t first, int n,
                     LaneHits& out) {
    out.mask = 0;
    for (int i = 0; i < n; ++i) {
        const float* at = rows + first + std::size_t(i);
        const auto corner = [&](int c) {
            return Float3{at[std::size_t(3 * c) * stride], at[std::size_t(3 * c + 1) * stride],
                          at[std::size_t(3 * c + 2) * stride]};
        };
        test_lane(r, Triangle{corner(0), corner(1), corner(2)}, i, out);
    }
}

void scalar_packet_x1(const WatertightPacket16& p, const Triangle& tri, LaneHits& out) {
    out.mask = 0;
    for (int i = 0; i < 16; ++i) {
        if (((p.active >> i) & 1u) == 0) continue;
        WatertightRay r;
        r.org = Float3{p.org_x[i], p.org_y[i], p.org_z[i]};
        r.kx = int(p.kx[i]);
        r.ky = int(p.ky[i]);
        r.kz = int(p.kz[i]);
        r.sx = p.sx[i];
        r.sy = p.sy[i];
        r.sz = p.sz[i];
        r.tnear = p.tnear[i];
        r.tfar = p.tfar[i];
        test_lane(r, tri, i, out);
    }
}

}  // namespace

template <>
const TriangleKernels& simd::table<TriangleKernels, Isa::scalar>() {
    static constexpr TriangleKernels kScalar{Isa::scalar, scalar_ray_xn, scalar_ray_xn, scalar_packet_x1,
                                             scalar_ray_rows};
    return kScalar;
}

const TriangleKernels& triangle_kernels(Isa isa) { return simd::select<TriangleKernels>(isa); }

}  // namespace beamtrace
