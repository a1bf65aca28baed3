#pragma once
// The AVX-512 kernel of tile_ray_store.hpp; included only by kernels_avx512.cpp. The 16 words of
// the 16 lanes' records are made as 16 registers (word w of every lane in register w), transposed
// 16 x 16 in registers (32-bit unpacks, 64-bit unpacks, two rounds of 128-bit lane shuffles), and
// each lane's record leaves as one 64-byte streaming store.
#include <cstdint>

#include <immintrin.h>

#include "vlf/stream/tile_ray_store.hpp"

namespace beamtrace::vlf {
namespace {

#if defined(__AVX512F__)
[[maybe_unused]] void store_tile_rays_avx512(const PacketLookup& l, const Packet16& p, std::uint32_t lanes,
                                             std::uint32_t tiles_per_side, std::uint32_t slot0, TileRay* const* to) {
    if (lanes == 0) return;
    auto ints = [](const void* a) { return _mm512_loadu_si512(a); };
    const __m512i zero = _mm512_setzero_si512(), one = _mm512_set1_epi32(1);
    const __m512i kx = ints(l.kx), ky = ints(l.ky), kz = ints(l.kz);
    const __m512i ox = ints(p.org_x), oy = ints(p.org_y), oz = ints(p.org_z);
    // The origin's component k of each lane (k in {0, 1, 2}).
    auto pick = [&](const __m512i& k) {
        __m512i r = _mm512_mask_mov_epi32(oz, _mm512_cmpeq_epi32_mask(k, zero), ox);
        return _mm512_mask_mov_epi32(r, _mm512_cmpeq_epi32_mask(k, one), oy);
    };
    const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    __m512i v[16] = {
        _mm512_add_epi32(_mm512_mullo_epi32(ints(l.row), _mm512_set1_epi32(int(tiles_per_side))), ints(l.column)),
        _mm512_add_epi32(_mm512_set1_epi32(int(slot0)), iota),
        ints(l.z0),
        ints(l.z1),
        ints(l.footprint),
        pick(kx),
        pick(ky),
        pick(kz),
        ints(l.sx),
        ints(l.sy),
        ints(l.sz),
        ints(p.tnear),
        ints(p.tfar),
        kx,
        ky,
        kz};
    __m512i t[16];
    for (int i = 0; i < 8; ++i) {
        t[2 * i] = _mm512_unpacklo_epi32(v[2 * i], v[2 * i + 1]);
        t[2 * i + 1] = _mm512_unpackhi_epi32(v[2 * i], v[2 * i + 1]);
    }
    // u[4 j + c], 128-bit lane L: words 4 j .. 4 j + 3 of lane 4 L + c.
    for (int j = 0; j < 4; ++j) {
        v[4 * j + 0] = _mm512_unpacklo_epi64(t[4 * j], t[4 * j + 2]);
        v[4 * j + 1] = _mm512_unpackhi_epi64(t[4 * j], t[4 * j + 2]);
        v[4 * j + 2] = _mm512_unpacklo_epi64(t[4 * j + 1], t[4 * j + 3]);
        v[4 * j + 3] = _mm512_unpackhi_epi64(t[4 * j + 1], t[4 * j + 3]);
    }
    for (int c = 0; c < 4; ++c) {
        const __m512i a = _mm512_shuffle_i32x4(v[c], v[4 + c], 0x44), b = _mm512_shuffle_i32x4(v[c], v[4 + c], 0xEE);
        const __m512i e = _mm512_shuffle_i32x4(v[8 + c], v[12 + c], 0x44),
                      d = _mm512_shuffle_i32x4(v[8 + c], v[12 + c], 0xEE);
        t[0 + c] = _mm512_shuffle_i32x4(a, e, 0x88);
        t[4 + c] = _mm512_shuffle_i32x4(a, e, 0xDD);
        t[8 + c] = _mm512_shuffle_i32x4(b, d, 0x88);
        t[12 + c] = _mm512_shuffle_i32x4(b, d, 0xDD);
    }
    for (std::uint32_t m = lanes; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        _mm512_stream_si512(reinterpret_cast<__m512i*>(to[i]), t[i]);
    }
}
#endif

}  // namespace
}  // namespace beamtrace::vlf
