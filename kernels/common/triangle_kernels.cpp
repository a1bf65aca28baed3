// Run-time choice of the triangle kernels, and the scalar set (the reference, lane by lane).
#include "common/triangle_kernels.hpp"

#include "beamtrace/error.hpp"
#include "common/triangle_reference.hpp"

namespace beamtrace {

namespace {

void scalar_ray_xn(const WatertightRay& r, const Triangle* const* tris, int n, LaneHits& out) {
    out.mask = 0;
    for (int i = 0; i < n; ++i) {
        TriangleHit h;
        if (intersect_triangle(r, *tris[i], h)) {
            out.t[i] = h.t; out.u[i] = h.u; out.v[i] = h.v;
            out.mask |= 1u << i;
        }
    }
}

void scalar_packet_x1(const WatertightPacket16& p, const Triangle& tri, LaneHits& out) {
    out.mask = 0;
    for (int i = 0; i < 16; ++i) {
        if (((p.active >> i) & 1u) == 0) continue;
        WatertightRay r;
        r.org = Float3{p.org_x[i], p.org_y[i], p.org_z[i]};
        r.kx = int(p.kx[i]); r.ky = int(p.ky[i]); r.kz = int(p.kz[i]);
        r.sx = p.sx[i]; r.sy = p.sy[i]; r.sz = p.sz[i];
        r.tnear = p.tnear[i]; r.tfar = p.tfar[i];
        TriangleHit h;
        if (intersect_triangle(r, tri, h)) {
            out.t[i] = h.t; out.u[i] = h.u; out.v[i] = h.v;
            out.mask |= 1u << i;
        }
    }
}

constexpr TriangleKernels kScalar{Isa::scalar, scalar_ray_xn, scalar_ray_xn, scalar_packet_x1};
constexpr TriangleKernels kSse42{Isa::sse42, kernels_sse42::ray_x4, kernels_sse42::ray_x8, kernels_sse42::packet_x1};
constexpr TriangleKernels kAvx2{Isa::avx2, kernels_sse42::ray_x4, kernels_avx2::ray_x8, kernels_avx2::packet_x1};
constexpr TriangleKernels kAvx512{Isa::avx512, kernels_sse42::ray_x4, kernels_avx2::ray_x8,
                                  kernels_avx512::packet_x1};

}  // namespace

const TriangleKernels& triangle_kernels(Isa isa) {
    if (!isa_available(isa)) throw Error(std::string("instruction set ") + isa_name(isa) + " is not available");
    switch (isa) {
        case Isa::scalar: return kScalar;
        case Isa::sse42: return kSse42;
        case Isa::avx2: return kAvx2;
        case Isa::avx512: return kAvx512;
    }
    return kScalar;
}

}  // namespace beamtrace
