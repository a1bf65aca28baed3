// make_watertight_packet in SSE (the library's baseline): the dominant axis, the axis order, the
// shear and the copies of every lane, four lanes at a time, with the same operations as
// make_watertight_ray (compares, selects, and divisions, which round the same in any width).
#include <bit>

#include "simd/sse_lanes.hpp"
#include "common/watertight_ray.hpp"

namespace beamtrace {

WatertightPacket16 make_watertight_packet(const Packet16& p) {
    using B = sse::Floats;
    constexpr int W = int(B::size);
    WatertightPacket16 w;
    const B zero(0.0f), one(1.0f), two(2.0f);
    for (int base = 0; base < 16; base += W) {
        const sse::Mask on = sse::lanes_on(p.active >> base);
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
        (pick(kx) / dkz).store_unaligned(w.sx + base);
        (pick(ky) / dkz).store_unaligned(w.sy + base);
        (one / dkz).store_unaligned(w.sz + base);
        kx.store_unaligned(w.kx + base);
        ky.store_unaligned(w.ky + base);
        kz.store_unaligned(w.kz + base);
    }
    for (int i = 0; i < 16; ++i) {
        w.org_x[i] = p.org_x[i];
        w.org_y[i] = p.org_y[i];
        w.org_z[i] = p.org_z[i];
        w.tnear[i] = p.tnear[i];
        w.tfar[i] = p.tfar[i];
    }
    w.active = p.active & 0xFFFFu;
    if (w.active != 0) {
        const int f = __builtin_ctz(w.active);
        w.first = f;
        w.axis[0] = int(w.kx[f]);
        w.axis[1] = int(w.ky[f]);
        w.axis[2] = int(w.kz[f]);
        w.same_axes = w.same_origin = true;
        for (std::uint32_t b = w.active; b; b &= b - 1) {
            const int i = __builtin_ctz(b);
            w.same_axes = w.same_axes && w.kx[i] == w.kx[f] && w.ky[i] == w.ky[f] && w.kz[i] == w.kz[f];
            // Bit patterns, not values: 0 and -0 give differently signed differences.
            w.same_origin = w.same_origin &&
                            std::bit_cast<std::uint32_t>(w.org_x[i]) == std::bit_cast<std::uint32_t>(w.org_x[f]) &&
                            std::bit_cast<std::uint32_t>(w.org_y[i]) == std::bit_cast<std::uint32_t>(w.org_y[f]) &&
                            std::bit_cast<std::uint32_t>(w.org_z[i]) == std::bit_cast<std::uint32_t>(w.org_z[f]);
        }
    }
    return w;
}

}  // namespace beamtrace
