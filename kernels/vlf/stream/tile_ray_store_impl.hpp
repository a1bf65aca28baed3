#pragma once
// The AVX-512 kernel of tile_ray_store.hpp; included only by kernels_avx512.cpp. The 16 words of
// the 16 lanes' records are made as 16 registers (word w of every lane in register w), transposed
// 16 x 16 in registers (simd/transpose16_impl.hpp), and each lane's record leaves as one 64-byte
// streaming store.
#include <cstdint>

#include <immintrin.h>

#include "simd/transpose16_impl.hpp"
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
    simd::transpose16_epi32(v);
    for (std::uint32_t m = lanes; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        _mm512_stream_si512(reinterpret_cast<__m512i*>(to[i]), v[i]);
    }
}
#endif

}  // namespace
}  // namespace beamtrace::vlf
