#pragma once
// One ray's walk through the PSF its lookup chose, in either mode: shared by the single-ray and the
// packet queries of VisibilityField.
#include "vlf/tile_walk.hpp"
#include "vlf/vlf_impl.hpp"

namespace beamtrace::vlf {

template <bool kOcclusion, bool kCount>
Hit walk_field(const VisibilityField::Impl& f, const ParallelSubfield& psf, const CanonicalRay& cr,
               const WatertightRay& ray, VlfMode mode, VlfCounters* counters) {
    const WalkContext ctx{&f.grid, f.triangles.data(), f.triangles.size(), f.kernels, f.simd->scan_footprints};
    if (mode == VlfMode::fast) return TileWalk<kOcclusion, true, kCount>(psf, ctx, ray, counters).run(cr);
    return TileWalk<kOcclusion, false, kCount>(psf, ctx, ray, counters).run(cr);
}

}  // namespace beamtrace::vlf
