#pragma once
// The lookups of a 4x4 packet at once: 16 rays -> 16 PSF indices, 16 canonical rays cut to the
// scene's box, 16 first tiles. Written once over xsimd batches (packet_lookup_impl.hpp), compiled
// per instruction set and chosen at run time like the triangle kernels; every lane equals what the
// single-ray set-up (direction_set_impl.hpp, canonical_ray.hpp) computes, bit for bit.
#include <cstdint>
#include <vector>

#include "beamtrace/ray.hpp"
#include "simd/isa.hpp"
#include "common/watertight_ray.hpp"
#include "vlf/directions/canonical_frame.hpp"
#include "vlf/directions/canonical_ray.hpp"

namespace beamtrace::vlf {

// What the lookups read.
struct LookupTables {
    // Direction set: directions (structure of arrays) and the candidate table, read as 32-bit
    // words of two 16-bit candidates each (pairs_per_cell words per cell).
    const float* dir_x = nullptr;
    const float* dir_y = nullptr;
    const float* dir_z = nullptr;
    const std::int32_t* candidate_pairs = nullptr;
    int table = 0, pairs_per_cell = 0;
    float half_table = 0.0f;
    // Frames: component c (e1.x, e1.y, e1.z, e2.x, ..., e3.z) of direction i at frames[c * count + i].
    const double* frames = nullptr;
    int count = 0;
    // Grid and box.
    double centre[3] = {0, 0, 0};
    double radius = 0.0, inv_h = 0.0;
    double h = 0.0, pad = 0.0, lattice_scale = 0.0;  // tile side, padding, footprint lattice (TileGrid)
    int tiles = 1;
    WorldBox box{};
};

struct alignas(64) PacketLookup {
    std::uint32_t psf[16];
    double ox[16], oy[16], oz[16], dx[16], dy[16], dz[16], t0[16], t1[16];
    double inv_dx[16], inv_dy[16], inv_dz[16];
    std::int32_t column[16], row[16];
    // The watertight triangle test's set-up of each ray (make_watertight_ray).
    std::int32_t kx[16], ky[16], kz[16];
    float sx[16], sy[16], sz[16];
    // What a segment inside its first tile needs (tile_ray_stream.hpp), as tile_walk.hpp computes
    // it: the depths of its ends as floats, its footprint over [t0, t1] in that tile.
    float z0[16], z1[16];
    std::uint32_t footprint[16];
    std::uint32_t valid = 0;     // bit i: ray i is active, well formed and its segment meets the box
    std::uint32_t one_tile = 0;  // bit i (of valid lanes): the segment lies in its first tile

    CanonicalRay ray(int i) const {
        return CanonicalRay{ox[i], oy[i],     oz[i],  dx[i],     dy[i],     dz[i],    t0[i],
                            t1[i], column[i], row[i], inv_dx[i], inv_dy[i], inv_dz[i]};
    }
    WatertightRay watertight(int i, const Packet16& p) const {
        return {Float3{p.org_x[i], p.org_y[i], p.org_z[i]}, kx[i], ky[i], kz[i], sx[i], sy[i], sz[i], p.tnear[i],
                p.tfar[i]};
    }
};

// first_tiles: also z0, z1, footprint and one_tile (else those are left unset and one_tile is 0).
using LookupPacketFn = void (*)(const LookupTables& tables, const Packet16& packet, PacketLookup& out,
                                bool first_tiles);

// The tables of a field's direction set, frames, grid and box (the vector keeps the frames).
struct LookupStorage {
    std::vector<double> frames;
    LookupTables tables;
};

}  // namespace beamtrace::vlf
