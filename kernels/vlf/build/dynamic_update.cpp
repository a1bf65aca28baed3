// Dynamic scenes (section 8): "all PSFs are visited, and the object rasterised into the tiling
// coordinate system as usual, except that in this case the identifiers of the object are removed
// rather than added. Then the polygon's geometry is transformed, and reinserted."
//
// Every built PSF rebuilds the tile-BSPs of exactly the tiles the triangles touch, from the
// tile's current triangles, with the code of a fresh build; so after any sequence of updates each
// tile holds what a fresh build of the current geometry would put there, leaf for leaf.
#include <algorithm>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "beamtrace/error.hpp"
#include "vlf/vlf_impl.hpp"

namespace beamtrace {
namespace {

// Zero area in double precision, as the Scene decides it (such triangles are never hit).
bool zero_area(const Triangle& t) {
    const double ax = double(t.v1.x) - t.v0.x, ay = double(t.v1.y) - t.v0.y, az = double(t.v1.z) - t.v0.z;
    const double bx = double(t.v2.x) - t.v0.x, by = double(t.v2.y) - t.v0.y, bz = double(t.v2.z) - t.v0.z;
    return ay * bz - az * by == 0.0 && az * bx - ax * bz == 0.0 && ax * by - ay * bx == 0.0;
}

// Throws unless every id is in range, appears once, and is in the field (want_inserted) or not.
void check_ids(const VisibilityField::Impl& f, std::span<const std::uint32_t> ids, bool want_inserted,
               const char* what) {
    std::vector<std::uint32_t> sorted(ids.begin(), ids.end());
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t k = 0; k < sorted.size(); ++k) {
        const std::uint32_t id = sorted[k];
        if (id >= f.triangles.size())
            throw Error(std::string("VLF ") + what + ": triangle " + std::to_string(id) + " is out of range (" +
                        std::to_string(f.triangles.size()) + " triangles)");
        if (k > 0 && sorted[k - 1] == id)
            throw Error(std::string("VLF ") + what + ": triangle " + std::to_string(id) + " is given twice");
        if ((f.inserted[id] != 0) != want_inserted)
            throw Error(std::string("VLF ") + what + ": triangle " + std::to_string(id) +
                        (want_inserted ? " is not in the field (removed)" : " is in the field (remove it first)"));
    }
}

// The field's own indices (spatial_order.hpp) of the caller's ids.
std::vector<std::uint32_t> field_indices(const VisibilityField::Impl& f, std::span<const std::uint32_t> ids) {
    std::vector<std::uint32_t> own;
    own.reserve(ids.size());
    for (std::uint32_t id : ids) own.push_back(f.rank[id]);
    return own;
}

// Runs f(psf) on every built PSF, in parallel.
template <class F>
void each_built_psf(VisibilityField::Impl& field, F&& f) {
    std::vector<vlf::ParallelSubfield*> built;
    for (auto& p : field.psfs)
        if (p) built.push_back(p.get());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, built.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i < r.end(); ++i) f(*built[i]);
                      });
}

}  // namespace

void VisibilityField::remove(std::span<const std::uint32_t> ids) {
    Impl& f = *impl_;
    check_ids(f, ids, true, "remove");
    const std::vector<std::uint32_t> own = field_indices(f, ids);
    for (std::uint32_t id : ids) f.inserted[id] = 0;
    for (std::uint32_t k : own) f.present[k] = 0;
    const vlf::SubfieldInput input = f.input();
    if (f.options.lazy_tiles) f.tile_cache->refit(f.triangles, f.present);
    each_built_psf(f, [&](vlf::ParallelSubfield& psf) { psf.remove(own, input); });
}

void VisibilityField::transform(std::span<const std::uint32_t> ids, const Affine3& map) {
    Impl& f = *impl_;
    check_ids(f, ids, false, "transform");
    for (std::uint32_t id : ids) {
        Triangle& t = f.caller_triangles[id];
        t = Triangle{map.apply(t.v0), map.apply(t.v1), map.apply(t.v2)};
        f.triangles[f.rank[id]] = t;
    }
}

void VisibilityField::insert(std::span<const std::uint32_t> ids) {
    Impl& f = *impl_;
    check_ids(f, ids, false, "insert");
    for (std::uint32_t id : ids) {
        const Triangle& t = f.caller_triangles[id];
        for (const Float3& p : {t.v0, t.v1, t.v2})
            for (int k = 0; k < 3; ++k)
                if (!(p[k] >= f.bounds.lower[k] && p[k] <= f.bounds.upper[k]))
                    throw Error("VLF insert: triangle " + std::to_string(id) +
                                " lies outside the field's bounds (give VlfOptions::bounds room for moving triangles)");
    }
    for (std::uint32_t id : ids) {
        f.inserted[id] = 1;
        f.present[f.rank[id]] = zero_area(f.caller_triangles[id]) ? 0 : 1;
    }
    const std::vector<std::uint32_t> own = field_indices(f, ids);
    const vlf::SubfieldInput input = f.input();
    // Lazy tiles find their triangles through the tree: its boxes follow the moved corners.
    if (f.options.lazy_tiles) f.tile_cache->refit(f.triangles, f.present);
    each_built_psf(f, [&](vlf::ParallelSubfield& psf) { psf.insert(own, input); });
}

}  // namespace beamtrace
