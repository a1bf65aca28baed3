#pragma once
// Writing the TileRays of a looked-up packet (tile_ray_stream.hpp) into the pool of a binned
// stream: lane i of the packet to its own place to[i], by streaming stores (the pool is far larger
// than the caches, and a plain store would first read the line it overwrites). The scalar
// reference stores a record field by field (16 four-byte streaming stores a ray); the AVX-512
// kernel (tile_ray_store_impl.hpp) transposes the packet's 16 fields of 16 lanes in registers and
// stores each record as one 64-byte line. Both write the same bytes (tests/vlf/vlf_kernels_test.cpp).
#include <bit>
#include <cstddef>
#include <cstdint>

#include <immintrin.h>

#include "beamtrace/ray.hpp"
#include "vlf/stream/packet_lookup.hpp"
#include "vlf/stream/tile_ray_batch.hpp"

namespace beamtrace::vlf {

static_assert(offsetof(TileRay, tile) == 0 && offsetof(TileRay, slot) == 4 && offsetof(TileRay, z0) == 8 &&
                  offsetof(TileRay, z1) == 12 && offsetof(TileRay, footprint) == 16 && offsetof(TileRay, okx) == 20 &&
                  offsetof(TileRay, oky) == 24 && offsetof(TileRay, okz) == 28 && offsetof(TileRay, sx) == 32 &&
                  offsetof(TileRay, sy) == 36 && offsetof(TileRay, sz) == 40 && offsetof(TileRay, tnear) == 44 &&
                  offsetof(TileRay, tfar) == 48 && offsetof(TileRay, kx) == 52 && offsetof(TileRay, ky) == 56 &&
                  offsetof(TileRay, kz) == 60 && sizeof(TileRay) == 64,
              "the kernels write a TileRay as these 16 words");

// For each lane i in `lanes` (lanes of l with first tiles): the TileRay of ray i of p, slot
// slot0 + i, tile row * tiles_per_side + column, stored at to[i] (64-byte aligned).
using StoreTileRaysFn = void (*)(const PacketLookup& l, const Packet16& p, std::uint32_t lanes,
                                 std::uint32_t tiles_per_side, std::uint32_t slot0, TileRay* const* to);

inline void store_tile_rays_scalar(const PacketLookup& l, const Packet16& p, std::uint32_t lanes,
                                   std::uint32_t tiles_per_side, std::uint32_t slot0, TileRay* const* to) {
    auto bits = [](float x) { return std::bit_cast<int>(x); };
    for (std::uint32_t m = lanes; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        const float o[3] = {p.org_x[i], p.org_y[i], p.org_z[i]};
        const std::int32_t kx = l.kx[i], ky = l.ky[i], kz = l.kz[i];
        const int words[16] = {int(std::uint32_t(l.row[i]) * tiles_per_side + std::uint32_t(l.column[i])),
                               int(slot0 + std::uint32_t(i)),
                               bits(l.z0[i]),
                               bits(l.z1[i]),
                               int(l.footprint[i]),
                               bits(o[kx]),
                               bits(o[ky]),
                               bits(o[kz]),
                               bits(l.sx[i]),
                               bits(l.sy[i]),
                               bits(l.sz[i]),
                               bits(p.tnear[i]),
                               bits(p.tfar[i]),
                               kx,
                               ky,
                               kz};
        // Word by word, not through a copy on the stack: a 16-byte load of 4-byte stores cannot be
        // forwarded and waits for them to reach the cache.
        int* out = reinterpret_cast<int*>(to[i]);
        for (int k = 0; k < 16; ++k) _mm_stream_si32(out + k, words[k]);
    }
}

}  // namespace beamtrace::vlf
