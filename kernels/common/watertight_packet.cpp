// make_watertight_packet in SSE (the library's baseline): the dominant axis, the axis order, the
// shear and the copies of every lane, four lanes at a time, with the same operations as
// make_watertight_ray (compares, selects, and divisions, which round the same in any width).
#include <bit>

#include "simd/sse_lanes.hpp"
#include "common/watertight_ray.hpp"

namespace beamtrace {

WatertightPacket16 make_watertight_packet(const Packet16& p) {
    WatertightPacket16 w;
    make_watertight_packet(p, w);
    return w;
}

void make_watertight_packet(const Packet16& p, WatertightPacket16& w) {
    using B = sse::Floats;
    constexpr int W = int(B::size);
    w.same_axes = false;
    w.same_origin = false;
    w.axis[0] = 0;
    w.axis[1] = 1;
    w.axis[2] = 2;
    w.first = 0;
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
        // Four lanes at a time against lane f: the axes as values, the origins as bit patterns
        // (0 and -0 give differently signed differences).
        std::uint32_t axes = 0, origin = 0;
        const B fx(w.kx[f]), fy(w.ky[f]), fz(w.kz[f]);
        const __m128i ox = _mm_set1_epi32(std::bit_cast<int>(w.org_x[f])),
                      oy = _mm_set1_epi32(std::bit_cast<int>(w.org_y[f])),
                      oz = _mm_set1_epi32(std::bit_cast<int>(w.org_z[f]));
        auto same_bits = [](const float* v, const __m128i& o) {
            return _mm_cmpeq_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(v)), o);
        };
        for (int base = 0; base < 16; base += W) {
            const auto same = (B::load_unaligned(w.kx + base) == fx) & (B::load_unaligned(w.ky + base) == fy) &
                              (B::load_unaligned(w.kz + base) == fz);
            axes |= sse::bits_of(same) << base;
            const __m128i o = _mm_and_si128(_mm_and_si128(same_bits(w.org_x + base, ox), same_bits(w.org_y + base, oy)),
                                            same_bits(w.org_z + base, oz));
            origin |= std::uint32_t(_mm_movemask_ps(_mm_castsi128_ps(o))) << base;
        }
        w.same_axes = (axes & w.active) == w.active;
        w.same_origin = (origin & w.active) == w.active;
    }
}

}  // namespace beamtrace
