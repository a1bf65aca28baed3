#pragma once
// Occlusion of a batch of rays whose segments each stay in the tile where they start (section 7:
// "when a shadow ray ... lies along a PSF direction, both endpoints of that ray fall on the same
// tile ... [it] would simply need to traverse the associated tile BSP leaves"). A binned stream
// (tile_ray_stream.cpp) reduces each such ray to a TileRay and traces them 16 at a time, in two
// kernels instead of one walk per ray:
//
//   candidates: per ray, the entries of the leaves its depths span whose footprint meets the ray's
//               (tile_footprint.hpp), compressed into (ray, triangle) pairs;
//   test:       the pairs of all 16 rays, 16 at a time, each lane its own ray and triangle, by the
//               library's watertight test.
//
// A ray of an AO stream meets about three candidates; a one-ray kernel would test them in a 16-wide
// call with most lanes idle, the pairs of a batch fill the lanes. Occlusion is an OR over the pairs,
// so their order, and the pairs of rays found occluded before their turn (skipped), change nothing.
//
// The scalar references (this header), the AVX-512 kernels (tile_ray_batch_impl.hpp) and the AVX2
// ones (tile_ray_batch_avx2_impl.hpp) give the same pairs, in the same order, and the same bits
// (tests/vlf/vlf_kernels_test.cpp).
#include <cstdint>

#include "beamtrace/scene.hpp"
#include "common/triangle_reference.hpp"
#include "common/watertight_ray.hpp"
#include "vlf/build/packed_ids.hpp"
#include "vlf/query/tile_footprint.hpp"

namespace beamtrace::vlf {

// A ray of a stream whose segment lies in one tile, reduced to what its occlusion needs: 64 bytes.
struct alignas(64) TileRay {
    std::uint32_t tile;       // row * n + column
    std::uint32_t slot;       // packet * 16 + lane in the input
    float z0, z1;             // canonical depths of the segment's ends, as TileBspView::leaf compares them
    std::uint32_t footprint;  // of the whole segment (tile_footprint.hpp)
    float okx, oky, okz;      // origin components kx, ky, kz (the watertight set-up's permutation)
    float sx, sy, sz;         // the shear
    float tnear, tfar;
    std::int32_t kx, ky, kz;  // its axes
};

// Up to 16 rays of a batch, structure of arrays (lane i = ray i).
struct alignas(64) TileRayBatch {
    float okx[16], oky[16], okz[16];
    float sx[16], sy[16], sz[16];
    float tnear[16], tfar[16];
    std::int32_t kx[16], ky[16], kz[16];
    std::uint32_t slot[16];
    std::uint32_t count = 0;

    void set(std::uint32_t i, const TileRay& r) {
        okx[i] = r.okx;
        oky[i] = r.oky;
        okz[i] = r.okz;
        sx[i] = r.sx;
        sy[i] = r.sy;
        sz[i] = r.sz;
        tnear[i] = r.tnear;
        tfar[i] = r.tfar;
        kx[i] = r.kx;
        ky[i] = r.ky;
        kz[i] = r.kz;
        slot[i] = r.slot;
    }
    WatertightRay ray(std::uint32_t i) const {
        float o[3];
        o[kx[i]] = okx[i];
        o[ky[i]] = oky[i];
        o[kz[i]] = okz[i];
        return {Float3{o[0], o[1], o[2]}, kx[i], ky[i], kz[i], sx[i], sy[i], sz[i], tnear[i], tfar[i]};
    }
};

// Candidates of ray `lane` among the entries first .. first + count - 1 of a tile (groups,
// footprints and ids as TileBspView gives them): those whose footprint meets ray_footprint, in
// order, as pairs (out_lanes[n], out_ids[n]) = (lane, ids[k]); returns n. Entries are taken 16 at
// a time: from `first` on (k - first in the same 16) in a tile without groups (groups == nullptr)
// or a run of at most kDirectGroups groups, in their groups (k / 16 equal) in a longer one; unless `distinct` (entries
// of one leaf), an entry is dropped when an earlier passing entry of its 16 holds the same id (a straddling triangle
// sits in every leaf it overlaps; repeats in other groups stay: testing a pair twice changes no answer). A kernel may
// skip groups whose union footprint misses the ray's: they hold no passing entry. The outputs have room for count + 16.
// Runs of at most this many groups are scanned entry by entry (their footprints and ids are
// requested ahead); longer runs read the groups' union footprints first.
inline constexpr std::uint32_t kDirectGroups = 8;

using BatchCandidatesFn = std::uint32_t (*)(const std::uint32_t* groups, const std::uint32_t* footprints,
                                            PackedIds ids, std::uint32_t first, std::uint32_t count,
                                            std::uint32_t ray_footprint, bool distinct, std::uint32_t lane,
                                            std::uint32_t* out_ids, std::uint32_t* out_lanes);

inline std::uint32_t batch_candidates_scalar(const std::uint32_t* groups, const std::uint32_t* footprints,
                                             PackedIds ids, std::uint32_t first, std::uint32_t count,
                                             std::uint32_t ray_footprint, bool distinct, std::uint32_t lane,
                                             std::uint32_t* out_ids, std::uint32_t* out_lanes) {
    std::uint32_t n = 0;
    std::uint32_t group = 0xFFFFFFFFu, group_start = 0;
    const std::uint32_t g0 = first / 16, g1 = (first + count + 15) / 16;
    const std::uint32_t origin =
        groups == nullptr || g1 - g0 <= kDirectGroups ? first : 0;  // where the runs of 16 start
    for (std::uint32_t k = first; k < first + count; ++k) {
        if ((k - origin) / 16 != group) {
            group = (k - origin) / 16;
            group_start = n;
        }
        if (!footprints_meet(footprints[k], ray_footprint)) continue;
        bool repeat = false;
        if (!distinct)
            for (std::uint32_t c = group_start; c < n; ++c) repeat |= out_ids[c] == ids[k];
        if (repeat) continue;
        out_ids[n] = ids[k];
        out_lanes[n] = lane;
        ++n;
    }
    return n;
}

// The bits of the batch's rays that `count` pairs (lanes[p], ids[p]) find occluded, or'ed into
// `occluded` (pairs of rays already in it are not tested).
using BatchTestFn = std::uint32_t (*)(const TileRayBatch& rays, const Triangle* triangles, const std::uint32_t* ids,
                                      const std::uint32_t* lanes, std::uint32_t count, std::uint32_t occluded);

inline std::uint32_t batch_test_scalar(const TileRayBatch& rays, const Triangle* triangles, const std::uint32_t* ids,
                                       const std::uint32_t* lanes, std::uint32_t count, std::uint32_t occluded) {
    for (std::uint32_t p = 0; p < count; ++p) {
        if ((occluded >> lanes[p]) & 1u) continue;
        TriangleHit h;
        if (intersect_triangle(rays.ray(lanes[p]), triangles[ids[p]], h)) occluded |= 1u << lanes[p];
    }
    return occluded;
}

}  // namespace beamtrace::vlf
