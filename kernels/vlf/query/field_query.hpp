#pragma once
// One ray's walk through the PSF its lookup chose, in either mode: shared by the single-ray and the
// packet queries of VisibilityField. A closest hit comes back with the caller's triangle id; an
// occlusion walk's hit only says that there is one.
#include "vlf/query/tile_walk.hpp"
#include "vlf/vlf_impl.hpp"

namespace beamtrace::vlf {

inline WalkContext walk_context(const VisibilityField::Impl& f) {
    return WalkContext{&f.grid,   f.triangles.data(),      f.triangles.size(),      f.order.data(),
                       f.kernels, f.simd->scan_footprints, f.simd->occlude_entries, f.simd->closest_entries};
}

template <bool kOcclusion, bool kCount>
Hit walk_field(const VisibilityField::Impl& f, const ParallelSubfield& psf, const CanonicalRay& cr,
               const WatertightRay& ray, VlfMode mode, QueryCounters* counters) {
    const WalkContext ctx = walk_context(f);
    // Occlusion along a segment inside one tile (AO rays along PSF directions, mode fast): one
    // fused kernel. The counting walks keep TileWalk, which tests the same triangles and counts them.
    if constexpr (kOcclusion && !kCount) {
        if (mode == VlfMode::fast ? segment_in_first_tile<true>(f.grid, cr)
                                  : segment_in_first_tile<false>(f.grid, cr)) {
            Hit h;
            const EntriesAnswer a = occlude_in_first_tile(psf, ctx, cr, ray, h.triangle);
            if (a != EntriesAnswer::too_many) return h;
        }
    }
    Hit h = mode == VlfMode::fast ? TileWalk<kOcclusion, true, kCount>(psf, ctx, ray, counters).run(cr)
                                  : TileWalk<kOcclusion, false, kCount>(psf, ctx, ray, counters).run(cr);
    if (!kOcclusion && h.hit()) h.triangle = f.order[h.triangle];  // the caller's id (spatial_order.hpp)
    return h;
}

}  // namespace beamtrace::vlf
