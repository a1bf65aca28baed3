// VisibilityField: options, construction, lazy (or eager) PSF builds, single-ray queries, statistics.
#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "beamtrace/error.hpp"
#include "common/ray_validity.hpp"
#include "vlf/directions/direction_set_impl.hpp"
#include "vlf/query/field_query.hpp"
#include "vlf/build/packed_ids.hpp"
#include "vlf/build/spatial_order.hpp"
#include "vlf/build/tile_cache.hpp"
#include "vlf/stream/tile_ray_stream.hpp"

namespace beamtrace {

void VlfOptions::validate() const {
    if (!DirectionSet::valid_count(directions)) DirectionSet{directions};  // throws, naming the valid counts
    if (tiles < 1 || tiles > 1024)
        throw Error("VLF tiles per side must be between 1 and 1024 (got " + std::to_string(tiles) + ")");
    if (depth < 0 || depth > 16)
        throw Error("VLF tile-BSP depth must be between 0 and 16 (got " + std::to_string(depth) + ")");
    if (memory_budget_bytes > 0 && !lazy_tiles)
        throw Error("a VLF memory budget needs lazy tiles (VlfOptions::lazy_tiles)");
    if (memory_budget_bytes > 0 && eager)
        throw Error("a VLF memory budget cannot be combined with an eager build (--vlf-eager builds every tile)");
    if (bounds) {
        const Box& b = *bounds;
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(b.lower[k]) || !std::isfinite(b.upper[k]) || b.lower[k] > b.upper[k])
                throw Error("VLF bounds must be a finite, non-empty box");
    }
}

VisibilityField::Impl::~Impl() {
    tile_cache->release_all();  // at once, not PSF by PSF
    psfs.clear();
}

VisibilityField::Impl::Impl(const Scene& scene, const VlfOptions& o)
    : options(o), directions((o.validate(), o.directions)) {
    bounds = o.bounds ? *o.bounds : scene.bounds();
    const Box& sb = scene.bounds();
    for (int k = 0; k < 3; ++k)
        if (sb.lower[k] < bounds.lower[k] || sb.upper[k] > bounds.upper[k])
            throw Error("VLF bounds do not contain the scene's box");
    grid = vlf::TileGrid::around(bounds, o.tiles);
    world_box = vlf::WorldBox::around(bounds, grid.pad);
    const std::size_t count = scene.triangle_count();
    if (count > vlf::kMaxFieldTriangles)  // tile entries keep 3-byte ids (packed_ids.hpp)
        throw Error("VLF fields hold at most " + std::to_string(vlf::kMaxFieldTriangles) + " triangles; the scene has " +
                    std::to_string(count));
    caller_triangles.assign(scene.triangles().begin(), scene.triangles().end());
    order = vlf::spatial_order(caller_triangles, bounds);
    rank.resize(count);
    triangles.resize(count);
    present.resize(count);
    for (std::size_t k = 0; k < count; ++k) {
        rank[order[k]] = std::uint32_t(k);
        triangles[k] = caller_triangles[order[k]];
        present[k] = scene.is_degenerate(order[k]) ? 0 : 1;
    }
    inserted.assign(count, 1);
    for (int i = 0; i < directions.size(); ++i) frames.push_back(vlf::CanonicalFrame::towards(directions.direction(i)));
    psfs.resize(std::size_t(directions.size()));
    ready = std::make_unique<std::atomic<const vlf::ParallelSubfield*>[]>(psfs.size());
    for (std::size_t i = 0; i < psfs.size(); ++i) ready[i].store(nullptr, std::memory_order_relaxed);
    build_locks = std::make_unique<std::mutex[]>(psfs.size());
    kernels = &triangle_kernels();
    std::size_t tile_budget = 0;
    if (o.memory_budget_bytes > 0) {
        const std::size_t fixed = base_bytes() + psfs.size() * psf_table_bytes() + tree_bytes(count);
        // Tiles get what the fixed part leaves: at least 64 KiB.
        if (o.memory_budget_bytes < fixed + (std::size_t(1) << 16))
            throw Error("VLF memory budget of " + std::to_string(o.memory_budget_bytes / (1 << 20)) +
                        " MiB is too small for this field: its fixed part (triangles, direction tables, one pointer "
                        "per tile of every PSF) takes " +
                        std::to_string(fixed / (1 << 20)) + " MiB, and tiles need at least 64 KiB more");
        tile_budget = o.memory_budget_bytes - fixed;
        // The streams' share (stream_packets), where the budget is large enough to spare it.
        const std::size_t streams = o.memory_budget_bytes / kStreamShare;
        if (tile_budget > 2 * streams) tile_budget -= streams;
    }
    tile_cache = std::make_unique<vlf::TileCache>(tile_budget);
    if (o.lazy_tiles) tile_cache->refit(triangles, present);
    // The packet lookup's tables.
    const DirectionSet::Impl& d = detail::Access::impl(directions);
    const std::size_t l = frames.size();
    lookup.frames.resize(9 * l);
    for (std::size_t i = 0; i < l; ++i) {
        const vlf::Vec3d rows[3] = {frames[i].e1, frames[i].e2, frames[i].e3};
        for (int r = 0; r < 3; ++r) {
            lookup.frames[(3 * r + 0) * l + i] = rows[r].x;
            lookup.frames[(3 * r + 1) * l + i] = rows[r].y;
            lookup.frames[(3 * r + 2) * l + i] = rows[r].z;
        }
    }
    vlf::LookupTables& t = lookup.tables;
    t.dir_x = d.dx.data();
    t.dir_y = d.dy.data();
    t.dir_z = d.dz.data();
    t.candidate_pairs = reinterpret_cast<const std::int32_t*>(d.candidate_pairs.data());
    t.table = d.table;
    t.pairs_per_cell = d.per_cell / 2;
    t.half_table = d.half_table;
    t.frames = lookup.frames.data();
    t.count = int(l);
    t.centre[0] = grid.centre.x;
    t.centre[1] = grid.centre.y;
    t.centre[2] = grid.centre.z;
    t.radius = grid.radius;
    t.inv_h = grid.inv_h;
    t.h = grid.h;
    t.pad = grid.pad;
    t.lattice_scale = grid.lattice_scale;
    t.tiles = grid.n;
    t.box = world_box;
    simd = &vlf::vlf_kernels(kernels->isa);
}

const vlf::ParallelSubfield& VisibilityField::Impl::build(std::uint32_t i) const {
    std::lock_guard<std::mutex> lock(build_locks[i]);
    if (const vlf::ParallelSubfield* p = ready[i].load(std::memory_order_acquire)) return *p;
    if (options.lazy_tiles)
        psfs[i] = std::make_unique<vlf::ParallelSubfield>(frames[i], input(), *tile_cache);
    else
        psfs[i] = std::make_unique<vlf::ParallelSubfield>(frames[i], input());
    ready[i].store(psfs[i].get(), std::memory_order_release);
    return *psfs[i];
}

std::size_t VisibilityField::Impl::base_bytes() const {
    return directions.memory_bytes() + triangles.size() * (2 * sizeof(Triangle) + 2 + 8) +
           frames.size() * sizeof(vlf::CanonicalFrame);
}

std::size_t VisibilityField::Impl::tree_bytes(std::size_t triangles) {
    const std::size_t runs = std::max<std::size_t>(1, (triangles + vlf::TriangleBoxTree::kLeaf - 1) / vlf::TriangleBoxTree::kLeaf);
    return 2 * std::bit_ceil(runs) * 6 * sizeof(float);
}

std::size_t VisibilityField::fixed_memory_bytes(std::size_t triangles, const VlfOptions& o) {
    o.validate();
    const DirectionSet d(o.directions);
    const std::size_t tiles = std::size_t(o.tiles) * std::size_t(o.tiles);
    return d.memory_bytes() + triangles * (2 * sizeof(Triangle) + 2 + 8) +
           std::size_t(o.directions) * (sizeof(vlf::CanonicalFrame) + sizeof(vlf::ParallelSubfield) +
                                        tiles * (sizeof(std::atomic<std::uint32_t*>) + 1)) +
           Impl::tree_bytes(triangles);
}

std::size_t VisibilityField::Impl::psf_table_bytes() const {
    const std::size_t tiles = std::size_t(grid.n) * std::size_t(grid.n);
    return sizeof(vlf::ParallelSubfield) + tiles * (sizeof(std::atomic<std::uint32_t*>) + 1);
}

namespace {

template <bool kOcclusion, bool kCount>
Hit trace(const VisibilityField::Impl& f, const Ray& ray, VlfMode mode, QueryCounters* counters) {
    if constexpr (kCount) ++counters->rays;
    if (!describes_segment(ray)) return Hit{};
    const float s = std::fabs(ray.dir.x) + std::fabs(ray.dir.y) + std::fabs(ray.dir.z);
    if (!(s > 0.0f && s < kInfinity)) return Hit{};
    const DirectionSet::Nearest nearest = detail::Access::impl(f.directions).nearest(ray.dir.x, ray.dir.y, ray.dir.z);
    const auto guard = f.reading();
    vlf::CanonicalRay cr;
    if (!vlf::make_canonical_ray(f.frames[nearest.index], f.grid, f.world_box, ray, cr)) return Hit{};
    return vlf::walk_field<kOcclusion, kCount>(f, f.psf(nearest.index), cr, make_watertight_ray(ray), mode, counters);
}

}  // namespace

VisibilityField::VisibilityField(const Scene& scene, const VlfOptions& options, const Progress& progress)
    : impl_(std::make_unique<Impl>(scene, options)) {
    if (options.eager) build_all(progress);
}
VisibilityField::~VisibilityField() = default;
VisibilityField::VisibilityField(VisibilityField&&) noexcept = default;
VisibilityField& VisibilityField::operator=(VisibilityField&&) noexcept = default;

Hit VisibilityField::intersect(const Ray& ray, VlfMode mode) const {
    return trace<false, false>(*impl_, ray, mode, nullptr);
}
bool VisibilityField::occluded(const Ray& ray, VlfMode mode) const {
    return trace<true, false>(*impl_, ray, mode, nullptr).hit();
}
Hit VisibilityField::intersect(const Ray& ray, VlfMode mode, QueryCounters& c) const {
    return trace<false, true>(*impl_, ray, mode, &c);
}
bool VisibilityField::occluded(const Ray& ray, VlfMode mode, QueryCounters& c) const {
    return trace<true, true>(*impl_, ray, mode, &c).hit();
}

void VisibilityField::build_all(const Progress& progress) {
    const Impl& f = *impl_;
    if (f.options.memory_budget_bytes > 0)
        throw Error("VisibilityField::build_all: the field has a memory budget; its tiles are built as rays need them");
    const std::size_t count = f.psfs.size();
    std::atomic<std::size_t> done{0};
    std::mutex report;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            const vlf::ParallelSubfield& p = f.psf(std::uint32_t(i));
            if (p.lazy()) p.build_all_tiles();
            const std::size_t k = ++done;
            if (progress) {
                std::lock_guard<std::mutex> lock(report);
                progress(double(k) / double(count));
            }
        }
    });
}

const DirectionSet& VisibilityField::directions() const { return impl_->directions; }
const VlfOptions& VisibilityField::options() const { return impl_->options; }
std::span<const Triangle> VisibilityField::triangles() const { return impl_->caller_triangles; }
bool VisibilityField::contains(std::uint32_t id) const {
    return id < impl_->inserted.size() && impl_->inserted[id] != 0;
}

VlfStats VisibilityField::stats() const {
    const Impl& f = *impl_;
    VlfStats s;
    s.directions = f.options.directions;
    s.tiles = f.options.tiles;
    s.depth = f.options.depth;
    s.memory_bytes = f.base_bytes();
    f.for_each_built([&](std::size_t, const vlf::ParallelSubfield& p) {
        ++s.psfs_built;
        s.tile_entries += p.entries();
        s.leaves += p.leaves();
        s.memory_bytes += p.memory_bytes();
        s.build_seconds += p.build_seconds();
    });
    const vlf::TileCacheStats t = f.tile_cache->stats();
    s.tile_entries += t.entries;
    s.leaves += t.leaves;
    s.build_seconds += t.build_seconds;
    s.tiles_built = t.tiles_built;
    s.tiles_evicted = t.tiles_evicted;
    s.tiles_resident = t.resident_tiles;
    s.rebuild_seconds = t.rebuild_seconds;
    // Whole PSFs and tile tables only grow; tiles are tracked at their peak.
    s.memory_peak_bytes = s.memory_bytes + f.tile_cache->tree.memory_bytes() + t.peak_tile_bytes;
    s.memory_bytes += f.tile_cache->memory_bytes();
    {
        std::lock_guard<std::mutex> lock(f.stream_bins_lock);
        for (const auto& b : f.stream_bins) s.stream_bytes += b->bytes();
    }
    return s;
}

}  // namespace beamtrace
