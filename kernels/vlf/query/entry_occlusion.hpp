#pragma once
// Occlusion by a run of tile entries: the fused kernel of a ray whose segment stays in one tile
// (section 7: an AO ray along a PSF direction always does; so does any ray in mode fast). The
// entries of the tile-BSP leaves the segment spans are scanned for footprints meeting the ray's
// (tile_footprint.hpp); the triangles that pass, each id once (its first entry: a triangle that
// straddles a split sits in both leaves), are tested in entry order with the watertight test.
// Up to kEntryCandidates triangles are tested at once (one 16-wide SIMD test); more than that and
// the kernel decides nothing, and the caller walks the tile as TileWalk does.
//
// The scalar reference (this header) and the SIMD kernels (entry_occlusion_impl.hpp) give the
// same answer and the same first hitting triangle, bit for bit (tests/vlf/vlf_kernels_test.cpp).
#include <cstdint>

#include "beamtrace/scene.hpp"
#include "common/triangle_reference.hpp"
#include "common/watertight_ray.hpp"
#include "vlf/build/packed_ids.hpp"
#include "vlf/query/tile_footprint.hpp"

namespace beamtrace::vlf {

enum class EntriesAnswer : std::uint32_t { clear, hit, too_many };
inline constexpr std::uint32_t kEntryCandidates = 16;

// count entries (footprints[k], ids[k]) against ray_footprint; *hit = the first id hit. distinct:
// the caller knows the ids are distinct (entries of one leaf), so no repeats are looked for.
using OccludeEntriesFn = EntriesAnswer (*)(const WatertightRay& ray, const Triangle* triangles,
                                           const std::uint32_t* footprints, PackedIds ids,
                                           std::uint32_t count, std::uint32_t ray_footprint, bool distinct,
                                           std::uint32_t* hit);

inline EntriesAnswer occlude_entries_scalar(const WatertightRay& ray, const Triangle* triangles,
                                            const std::uint32_t* footprints, PackedIds ids,
                                            std::uint32_t count, std::uint32_t ray_footprint, bool distinct,
                                            std::uint32_t* hit) {
    std::uint32_t candidates[kEntryCandidates];
    std::uint32_t n = 0;
    for (std::uint32_t k = 0; k < count; ++k) {
        if (!footprints_meet(footprints[k], ray_footprint)) continue;
        bool repeat = false;
        if (!distinct)
            for (std::uint32_t c = 0; c < n; ++c) repeat |= candidates[c] == ids[k];
        if (repeat) continue;
        if (n == kEntryCandidates) return EntriesAnswer::too_many;
        candidates[n++] = ids[k];
    }
    for (std::uint32_t c = 0; c < n; ++c) {
        TriangleHit h;
        if (intersect_triangle(ray, triangles[candidates[c]], h)) {
            *hit = candidates[c];
            return EntriesAnswer::hit;
        }
    }
    return EntriesAnswer::clear;
}

}  // namespace beamtrace::vlf
