#pragma once
// The state of a VisibilityField: its copy of the triangles, the direction set, the grid, one frame
// per direction and the PSFs, each built the first time a query needs it.
#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

#include "beamtrace/vlf.hpp"
#include "common/access.hpp"
#include "common/triangle_kernels.hpp"
#include "vlf/directions/canonical_frame.hpp"
#include "vlf/directions/canonical_ray.hpp"
#include "vlf/stream/packet_lookup.hpp"
#include "vlf/vlf_kernels.hpp"
#include "vlf/build/parallel_subfield.hpp"

namespace beamtrace {

namespace vlf {
class TileRayBins;
}

struct VisibilityField::Impl {
    VlfOptions options;
    DirectionSet directions;
    vlf::TileGrid grid;
    Box bounds;               // the volume triangles must stay in
    vlf::WorldBox world_box;  // bounds grown by the padding: rays are cut to it
    // Triangles are stored in spatial order (spatial_order.hpp): triangle k of the field is the
    // caller's triangle order[k], and caller's triangle i is the field's rank[i]. PSFs, walks and
    // kernels use the field's indices; the public API the caller's ids.
    std::vector<std::uint32_t> order, rank;
    std::vector<Triangle> triangles;         // current corners, field order
    std::vector<Triangle> caller_triangles;  // the same, caller's order (VisibilityField::triangles)
    std::vector<std::uint8_t> inserted;      // caller's order: in the field (not removed)
    std::vector<std::uint8_t> present;       // field order: inserted and of non-zero area: what PSFs hold
    std::vector<vlf::CanonicalFrame> frames;
    const TriangleKernels* kernels = nullptr;
    vlf::LookupStorage lookup;              // what the packet lookup reads
    const vlf::VlfKernels* simd = nullptr;  // packet lookup and footprint scan

    // Lazy tiles' blocks, their budget and their readers (tile_cache.hpp); always there (without
    // lazy tiles or a budget its guards do nothing). Before psfs: it outlives them.
    std::unique_ptr<vlf::TileCache> tile_cache;
    // PSF i, once built, is psfs[i]; ready[i] publishes it to queries without a lock.
    mutable std::vector<std::unique_ptr<vlf::ParallelSubfield>> psfs;
    mutable std::unique_ptr<std::atomic<const vlf::ParallelSubfield*>[]> ready;
    mutable std::unique_ptr<std::mutex[]> build_locks;
    // Bins of binned occlusion streams (tile_ray_stream.hpp): one per stream running at a time,
    // kept for the next stream (so that a pass does not pay for fresh pages) and freed with the
    // field. Lent by TileRayLease.
    mutable std::mutex stream_bins_lock;
    mutable std::vector<std::unique_ptr<vlf::TileRayBins>> stream_bins;

    Impl(const Scene& scene, const VlfOptions& options);
    ~Impl();  // in visibility_field.cpp, where TileRayBins is complete

    vlf::SubfieldInput input() const { return vlf::SubfieldInput{&grid, triangles, present, options.depth}; }
    // PSF i, built now if no query has needed it yet (thread-safe).
    const vlf::ParallelSubfield& psf(std::uint32_t i) const {
        if (const vlf::ParallelSubfield* p = ready[i].load(std::memory_order_acquire)) return *p;
        return build(i);
    }
    const vlf::ParallelSubfield& build(std::uint32_t i) const;
    // What every PSF costs before any tile is built, and the field without PSFs.
    std::size_t base_bytes() const;
    std::size_t psf_table_bytes() const;
    static std::size_t tree_bytes(std::size_t triangles);  // an upper bound for TriangleBoxTree
    // Around a query (a no-op without a budget) and where a reader holds no tile (tile_cache.hpp).
    vlf::TileCache::ReadGuard reading() const { return vlf::TileCache::ReadGuard(*tile_cache); }
    void quiescent() const { tile_cache->quiescent(); }
    // Under a memory budget an eighth of it goes to the buffers of binned streams (64-byte records
    // and the bins' partly filled chunks: counted as 80 bytes a ray), which then take at most this
    // many packets at a time.
    static constexpr std::size_t kStreamShare = 8, kStreamBytesPerRay = 80;
    std::size_t stream_packets() const {
        if (options.memory_budget_bytes == 0) return ~std::size_t(0) / 2;
        return std::max<std::size_t>(1024, options.memory_budget_bytes / kStreamShare / kStreamBytesPerRay / 16);
    }
    // The built PSFs (for updates and statistics).
    template <class F>
    void for_each_built(F&& f) const {
        for (std::size_t i = 0; i < psfs.size(); ++i)
            if (const vlf::ParallelSubfield* p = ready[i].load(std::memory_order_acquire)) f(i, *p);
    }
};

}  // namespace beamtrace
