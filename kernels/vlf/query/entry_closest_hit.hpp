#pragma once
// Closest hit among the entries of one tile-BSP leaf: the fused kernel of the closest-hit walk
// (tile_walk.hpp), one call per leaf. The entries whose footprint meets the ray's (tile_footprint.hpp)
// and whose triangle the ray has not tested yet (the walk's short list of tested ids, mailbox.hpp)
// are tested at once; the nearest hit no farther than ray.tfar (ties: the smaller order[id], the
// caller's id) replaces `best`, and the tested ids join the list. As TileWalk's own leaf loop does, with the
// same watertight test: the same answer, bit for bit.
//
// The kernel decides nothing (returns false, changes nothing) when more than kEntryCandidates
// entries pass or the list would overflow; the walk then takes the leaf itself.
//
// The scalar reference (this header) and the SIMD kernel (entry_closest_hit_impl.hpp, AVX-512)
// are compared in tests/vlf/vlf_kernels_test.cpp.
#include <cstdint>

#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"
#include "common/triangle_reference.hpp"
#include "common/watertight_ray.hpp"
#include "vlf/query/entry_occlusion.hpp"
#include "vlf/query/tile_footprint.hpp"

namespace beamtrace::vlf {

// The walk's list of tested ids: count ids, room for `room` (and 16 more words that SIMD kernels may
// write past the end of the list).
struct TestedIds {
    std::uint32_t* ids;
    std::uint32_t count;
    std::uint32_t room;
};

// count entries (footprints[k], ids[k], ids distinct) against ray_footprint.
using ClosestEntriesFn = bool (*)(const WatertightRay& ray, const Triangle* triangles, const std::uint32_t* order,
                                  const std::uint32_t* footprints, PackedIds ids, std::uint32_t count,
                                  std::uint32_t ray_footprint, TestedIds& tested, Hit& best);

// A hit at t on triangle id beats best: nearer, or as near on a smaller order[id] (the caller's id).
inline bool nearer_hit(float t, std::uint32_t id, const Hit& best, const std::uint32_t* order) {
    return t < best.t || (t == best.t && best.hit() && order[id] < order[best.triangle]);
}

inline bool closest_entries_scalar(const WatertightRay& ray, const Triangle* triangles, const std::uint32_t* order,
                                   const std::uint32_t* footprints, PackedIds ids, std::uint32_t count,
                                   std::uint32_t ray_footprint, TestedIds& tested, Hit& best) {
    std::uint32_t candidates[kEntryCandidates];
    std::uint32_t n = 0, fresh = 0;
    bool is_new[kEntryCandidates];
    for (std::uint32_t k = 0; k < count; ++k) {
        if (!footprints_meet(footprints[k], ray_footprint)) continue;
        if (n == kEntryCandidates) return false;
        bool seen = false;
        for (std::uint32_t c = 0; c < tested.count; ++c) seen |= tested.ids[c] == ids[k];
        is_new[n] = !seen;
        fresh += seen ? 0 : 1;
        candidates[n++] = ids[k];
    }
    if (tested.count + fresh > tested.room) return false;
    for (std::uint32_t c = 0; c < n; ++c) {
        if (!is_new[c]) continue;
        tested.ids[tested.count++] = candidates[c];
        TriangleHit h;
        if (intersect_triangle(ray, triangles[candidates[c]], h) && nearer_hit(h.t, candidates[c], best, order))
            best = Hit{h.t, candidates[c], h.u, h.v};
    }
    return true;
}

}  // namespace beamtrace::vlf
