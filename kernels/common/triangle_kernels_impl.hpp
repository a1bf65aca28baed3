#pragma once
// The watertight test written once over xsimd batches; included only by the per-ISA units, each of
// which instantiates it for its own architecture (lane_bits() from common/lane_bits.hpp).
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "simd/lane_bits.hpp"
#include "common/triangle_kernels.hpp"
#include "common/triangle_reference.hpp"

namespace beamtrace::simd {

// Triangle corners relative to the ray origin, already permuted to (kx, ky, kz) per lane.
template <class Arch>
struct Corners {
    using B = xsimd::batch<float, Arch>;
    B ax, ay, az, bx, by, bz, cx, cy, cz;
};

// The corners from corner(c, slot): corner c (0 = a, 1 = b, 2 = c) on the ray's axis `slot`
// (0 = kx, 1 = ky, 2 = kz). Inlined, so each call sees constant arguments.
template <class Arch, class Corner>
[[gnu::always_inline]] inline Corners<Arch> make_corners(const Corner& corner) {
    return {corner(0, 0), corner(0, 1), corner(0, 2), corner(1, 0), corner(1, 1),
            corner(1, 2), corner(2, 0), corner(2, 1), corner(2, 2)};
}

// The double-precision fallback of watertight_core, out of line: lanes where an edge function is
// exactly zero get all three again in double precision. Rare; kept out of the hot path so that the
// core needs no stack frame for the arrays it spills to.
template <class Arch>
[[gnu::noinline, gnu::cold]] void watertight_edges_exact(
    const xsimd::batch<float, Arch>& ax, const xsimd::batch<float, Arch>& ay, const xsimd::batch<float, Arch>& bx,
    const xsimd::batch<float, Arch>& by, const xsimd::batch<float, Arch>& cx, const xsimd::batch<float, Arch>& cy,
    xsimd::batch<float, Arch>& u, xsimd::batch<float, Arch>& v, xsimd::batch<float, Arch>& w) {
    using B = xsimd::batch<float, Arch>;
    constexpr int W = int(B::size);
    alignas(64) float su[W], sv[W], sw[W], fax[W], fay[W], fbx[W], fby[W], fcx[W], fcy[W];
    u.store_aligned(su);
    v.store_aligned(sv);
    w.store_aligned(sw);
    ax.store_aligned(fax);
    ay.store_aligned(fay);
    bx.store_aligned(fbx);
    by.store_aligned(fby);
    cx.store_aligned(fcx);
    cy.store_aligned(fcy);
    for (int i = 0; i < W; ++i) {
        if (su[i] == 0.0f || sv[i] == 0.0f || sw[i] == 0.0f)
            watertight_edges_double(fax[i], fay[i], fbx[i], fby[i], fcx[i], fcy[i], su[i], sv[i], sw[i]);
    }
    u = B::load_aligned(su);
    v = B::load_aligned(sv);
    w = B::load_aligned(sw);
}

// The shared core: shear, edge functions (with the double-precision fallback on lanes where one is
// exactly zero), sign test, determinant and distance. Writes t, u, v of hitting lanes into out at
// lane offset `base` and returns their bits (relative to base).
template <class Arch>
[[gnu::always_inline]] inline std::uint32_t watertight_core(const Corners<Arch>& k, const xsimd::batch<float, Arch>& sx,
                                                            const xsimd::batch<float, Arch>& sy,
                                                            const xsimd::batch<float, Arch>& sz,
                                                            const xsimd::batch<float, Arch>& tnear,
                                                            const xsimd::batch<float, Arch>& tfar,
                                                            std::uint32_t valid_bits, LaneHits& out, int base) {
    using B = xsimd::batch<float, Arch>;
    const B zero(0.0f);
    const B ax = k.ax - sx * k.az, ay = k.ay - sy * k.az;
    const B bx = k.bx - sx * k.bz, by = k.by - sy * k.bz;
    const B cx = k.cx - sx * k.cz, cy = k.cy - sy * k.cz;
    B u = cx * by - cy * bx;
    B v = ax * cy - ay * cx;
    B w = bx * ay - by * ax;
    if (lane_bits<Arch>((u == zero) | (v == zero) | (w == zero)) & valid_bits) [[unlikely]]
        watertight_edges_exact<Arch>(ax, ay, bx, by, cx, cy, u, v, w);
    const auto negative = (u < zero) | (v < zero) | (w < zero);
    const auto positive = (u > zero) | (v > zero) | (w > zero);
    // Most tests in traversal miss every ray on the edge signs alone (triangles of a leaf that fall
    // between a packet's rays): those lanes can never be inside, so stop before the determinant and
    // the division. Same bits as going on.
    const auto crossing = ~(negative & positive);
    if ((lane_bits<Arch>(crossing) & valid_bits) == 0) return 0;
    const B det = (u + v) + w;
    const B t_scaled = (u * (sz * k.az) + v * (sz * k.bz)) + w * (sz * k.cz);
    const B rcp = B(1.0f) / det;
    const B t = t_scaled * rcp;
    const auto inside = crossing & (det != zero) & (t >= tnear) & (t <= tfar) & (t < B(kInfinity));
    const std::uint32_t bits = lane_bits<Arch>(inside) & valid_bits;
    if (bits != 0) {
        t.store_aligned(out.t + base);
        (v * rcp).store_aligned(out.u + base);
        (w * rcp).store_aligned(out.v + base);
    }
    return bits;
}

// One ray against up to W triangles (lane i = tris[i]).
template <class Arch>
[[gnu::always_inline]] inline void ray_xw(const WatertightRay& r, const Triangle* const* tris, int n, LaneHits& out,
                                          int base) {
    using B = xsimd::batch<float, Arch>;
    constexpr int W = int(B::size);
    alignas(64) float comp[9][W];
    for (int i = 0; i < W; ++i) {
        const Triangle& tri = *tris[i < n ? i : 0];
        const float* f = &tri.v0.x;
        for (int c = 0; c < 9; ++c) comp[c][i] = f[c];
    }
    const float* o = &r.org.x;
    const int axis[3] = {r.kx, r.ky, r.kz};
    const Corners<Arch> k = make_corners<Arch>(
        [&](int c, int slot) { return B::load_aligned(comp[3 * c + axis[slot]]) - B(o[axis[slot]]); });
    const std::uint32_t valid = (n >= W) ? ((1u << W) - 1u) : ((1u << n) - 1u);
    out.mask |= watertight_core<Arch>(k, B(r.sx), B(r.sy), B(r.sz), B(r.tnear), B(r.tfar), valid, out, base) << base;
}

// One ray against n <= 16 consecutive triangles of corner rows (TriangleKernels::ray_rows), W lanes a
// step: the operations of ray_xw on the same values, loaded from the rows instead of copied.
template <class Arch>
[[gnu::always_inline]] inline void ray_rows(const WatertightRay& r, const float* rows, std::size_t stride,
                                            std::size_t first, int n, LaneHits& out) {
    using B = xsimd::batch<float, Arch>;
    constexpr int W = int(B::size);
    const float* o = &r.org.x;
    const int axis[3] = {r.kx, r.ky, r.kz};
    out.mask = 0;
    for (int base = 0; base < n; base += W) {
        const float* at = rows + first + std::size_t(base);
        const Corners<Arch> k = make_corners<Arch>([&](int c, int slot) {
            return B::load_unaligned(at + std::size_t(3 * c + axis[slot]) * stride) - B(o[axis[slot]]);
        });
        const int left = n - base;
        const std::uint32_t valid = left >= W ? (1u << W) - 1u : (1u << left) - 1u;
        out.mask |= watertight_core<Arch>(k, B(r.sx), B(r.sy), B(r.sz), B(r.tnear), B(r.tfar), valid, out, base)
                    << base;
    }
}

// Lanes [base, base + W) of a packet against one triangle.
template <class Arch>
[[gnu::always_inline]] inline void packet_xw(const WatertightPacket16& p, const Triangle& tri, LaneHits& out,
                                             int base) {
    using B = xsimd::batch<float, Arch>;
    constexpr int W = int(B::size);
    const std::uint32_t valid = (p.active >> base) & ((1u << W) - 1u);
    if (valid == 0) return;
    Corners<Arch> k;
    if (p.same_axes) {
        // One permutation for every lane: pick the corner components once (scalar), then subtract
        // the origin per lane, or once when it is shared. Same operations, same results.
        const float* v = &tri.v0.x;
        const int* axis = p.axis;
        const float* org[3] = {p.org_x, p.org_y, p.org_z};
        if (p.same_origin) {
            k = make_corners<Arch>([&](int c, int slot) {
                const int a = axis[slot];
                return B(v[3 * c + a] - org[a][p.first]);
            });
        } else {
            const B o[3] = {B::load_aligned(org[axis[0]] + base), B::load_aligned(org[axis[1]] + base),
                            B::load_aligned(org[axis[2]] + base)};
            k = make_corners<Arch>([&](int c, int slot) { return B(v[3 * c + axis[slot]]) - o[slot]; });
        }
    } else {
        const B kk[3] = {B::load_aligned(p.kx + base), B::load_aligned(p.ky + base), B::load_aligned(p.kz + base)};
        const B ox = B::load_aligned(p.org_x + base), oy = B::load_aligned(p.org_y + base),
                oz = B::load_aligned(p.org_z + base);
        const B one(1.0f), zero(0.0f);
        // The corners relative to the origin, then component kk (0, 1, 2) of each per lane; values
        // are moved, never rounded.
        const B rel[3][3] = {{B(tri.v0.x) - ox, B(tri.v0.y) - oy, B(tri.v0.z) - oz},
                             {B(tri.v1.x) - ox, B(tri.v1.y) - oy, B(tri.v1.z) - oz},
                             {B(tri.v2.x) - ox, B(tri.v2.y) - oy, B(tri.v2.z) - oz}};
        k = make_corners<Arch>([&](int c, int slot) {
            const B& which = kk[slot];
            return xsimd::select(which == zero, rel[c][0], xsimd::select(which == one, rel[c][1], rel[c][2]));
        });
    }
    out.mask |= watertight_core<Arch>(k, B::load_aligned(p.sx + base), B::load_aligned(p.sy + base),
                                      B::load_aligned(p.sz + base), B::load_aligned(p.tnear + base),
                                      B::load_aligned(p.tfar + base), valid, out, base)
                << base;
}

template <class Arch>
void packet_x1(const WatertightPacket16& p, const Triangle& tri, LaneHits& out) {
    constexpr int W = int(xsimd::batch<float, Arch>::size);
    out.mask = 0;
    for (int base = 0; base < 16; base += W) packet_xw<Arch>(p, tri, out, base);
}

}  // namespace beamtrace::simd
