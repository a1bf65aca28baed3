#pragma once
// make_watertight_packet written once over xsimd batches, W lanes a step: make_watertight_ray's
// compares, selects and divisions lane by lane, so its bits (make_watertight_packet_reference is the
// reference). Included by the per-ISA units and, at SSE4.2, by watertight_packet.cpp (the library's
// baseline form, compiled with the same flags as the SSE4.2 unit).
#include <bit>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "common/watertight_ray.hpp"
#include "simd/lane_bits.hpp"

namespace beamtrace::simd_impl {

template <class Arch>
void make_watertight_packet(const Packet16& p, WatertightPacket16& w) {
    using B = xsimd::batch<float, Arch>;
    using BI = xsimd::batch<std::int32_t, Arch>;
    using beamtrace::simd::lane_bits;
    constexpr int W = int(B::size);
    w.same_axes = false;
    w.same_origin = false;
    w.axis[0] = 0;
    w.axis[1] = 1;
    w.axis[2] = 2;
    w.first = 0;
    const B zero(0.0f), one(1.0f), two(2.0f);
    for (int base = 0; base < 16; base += W) {
        const auto on = beamtrace::simd::lanes_on<Arch>(p.active >> base);
        // Inactive lanes: direction (0, 0, 1), harmless values.
        const B dx = xsimd::select(on, B::load_unaligned(p.dir_x + base), zero);
        const B dy = xsimd::select(on, B::load_unaligned(p.dir_y + base), zero);
        const B dz = xsimd::select(on, B::load_unaligned(p.dir_z + base), one);
        const B ax = xsimd::abs(dx), ay = xsimd::abs(dy), az = xsimd::abs(dz);
        // kz = (ax > ay) ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2)
        const B kz = xsimd::select(ax > ay, xsimd::select(ax > az, zero, two), xsimd::select(ay > az, one, two));
        B kx = xsimd::select(kz == two, zero, kz + one);
        B ky = xsimd::select(kx == two, zero, kx + one);
        auto pick = [&](const B& k) { return xsimd::select(k == zero, dx, xsimd::select(k == one, dy, dz)); };
        const B dkz = pick(kz);
        const auto swap = dkz < zero;
        const B kx_swapped = xsimd::select(swap, ky, kx), ky_swapped = xsimd::select(swap, kx, ky);
        kx = kx_swapped;
        ky = ky_swapped;
        (pick(kx) / dkz).store_aligned(w.sx + base);
        (pick(ky) / dkz).store_aligned(w.sy + base);
        (one / dkz).store_aligned(w.sz + base);
        kx.store_aligned(w.kx + base);
        ky.store_aligned(w.ky + base);
        kz.store_aligned(w.kz + base);
        B::load_unaligned(p.org_x + base).store_aligned(w.org_x + base);
        B::load_unaligned(p.org_y + base).store_aligned(w.org_y + base);
        B::load_unaligned(p.org_z + base).store_aligned(w.org_z + base);
        B::load_unaligned(p.tnear + base).store_aligned(w.tnear + base);
        B::load_unaligned(p.tfar + base).store_aligned(w.tfar + base);
    }
    w.active = p.active & 0xFFFFu;
    if (w.active == 0) return;
    const int f = __builtin_ctz(w.active);
    w.first = f;
    w.axis[0] = int(w.kx[f]);
    w.axis[1] = int(w.ky[f]);
    w.axis[2] = int(w.kz[f]);
    // W lanes at a time against lane f: the axes as values, the origins as bit patterns (0 and -0
    // give differently signed differences).
    std::uint32_t axes = 0, origin = 0;
    const B fx(w.kx[f]), fy(w.ky[f]), fz(w.kz[f]);
    const BI ox(std::bit_cast<std::int32_t>(w.org_x[f])), oy(std::bit_cast<std::int32_t>(w.org_y[f])),
        oz(std::bit_cast<std::int32_t>(w.org_z[f]));
    auto same_bits = [](const float* v, const BI& o) { return xsimd::bitwise_cast<BI>(B::load_aligned(v)) == o; };
    for (int base = 0; base < 16; base += W) {
        const auto same = (B::load_aligned(w.kx + base) == fx) & (B::load_aligned(w.ky + base) == fy) &
                          (B::load_aligned(w.kz + base) == fz);
        axes |= lane_bits<Arch>(same) << base;
        const auto o = same_bits(w.org_x + base, ox) & same_bits(w.org_y + base, oy) & same_bits(w.org_z + base, oz);
        origin |= lane_bits<Arch>(xsimd::bool_cast(o)) << base;
    }
    w.same_axes = (axes & w.active) == w.active;
    w.same_origin = (origin & w.active) == w.active;
}

}  // namespace beamtrace::simd_impl
