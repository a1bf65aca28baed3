#pragma once
// ParallelSubfield (PSF): the n x n parallel beams of one direction (section 3.1) with their
// tile-BSPs, built in one of two ways:
// - whole: every triangle rasterised at once; one slot per tile and a pool of 32-bit words holding
//   every non-empty tile's TileBsp block (see tile_bsp.hpp), packed back to back. Dynamic updates
//   (section 8) rebuild the blocks of the tiles a moved triangle touches, in place when the new
//   block fits the old one's room, else at the end of the pool.
// - lazy tiles: a tile is built the first time a ray reaches it (tile()), from the triangles the
//   field's TriangleBoxTree gives for its beam, each kept exactly when the whole build would keep it
//   (TileRasteriser::touches, then the same clip): the same block, word for word. One atomic
//   pointer per tile; blocks belong to the field's TileCache (tile_cache.hpp), which may evict them
//   under a memory budget.
#include <algorithm>
#include <atomic>
#include <memory>
#include <cstdint>

#include <immintrin.h>
#include <span>
#include <vector>

#include "beamtrace/scene.hpp"
#include "vlf/directions/canonical_frame.hpp"
#include "vlf/build/prism_clip.hpp"
#include "vlf/build/tile_bsp.hpp"
#include "vlf/build/tile_cache.hpp"

namespace beamtrace::vlf {

// A tile as a query sees it.
struct TileRef {
    const std::uint32_t* block = nullptr;  // its TileBsp block
    std::uint32_t leaves = 0;              // 0: the tile's beam meets no triangle
};

// What a PSF is built from: the field's grid, its current triangles, and which of them are in the
// field (inserted and of non-zero area).
struct SubfieldInput {
    const TileGrid* grid = nullptr;
    std::span<const Triangle> triangles;
    std::span<const std::uint8_t> present;
    int depth = 4;
};

class ParallelSubfield {
public:
    // Whole: built now.
    ParallelSubfield(const CanonicalFrame& frame, const SubfieldInput& input);
    // Lazy tiles: nothing built yet; tiles are built by (and belong to) cache. input's spans must
    // outlive the PSF.
    ParallelSubfield(const CanonicalFrame& frame, const SubfieldInput& input, TileCache& cache);
    ~ParallelSubfield();
    ParallelSubfield(const ParallelSubfield&) = delete;
    ParallelSubfield& operator=(const ParallelSubfield&) = delete;

    const CanonicalFrame& frame() const { return frame_; }
    bool lazy() const { return cache_ != nullptr; }
    // The tile (built now if lazy and not built yet; thread-safe). Lazy tiles: valid until the
    // calling thread's next quiescent state (tile_cache.hpp).
    TileRef tile(std::uint32_t index) const {
        if (!cache_) {
            const Slot s = tiles_[index];
            return TileRef{pool_.data() + s.offset, s.leaves};
        }
        std::uint32_t* h = lazy_[index].load(std::memory_order_acquire);
        if (!h) [[unlikely]]
            h = cache_->build(*this, index);
        if (stamp_ && h[0]) {
            const std::uint32_t now = cache_->clock();
            std::atomic_ref<std::uint32_t> last(h[1]);
            if (last.load(std::memory_order_relaxed) != now) last.store(now, std::memory_order_relaxed);
        }
        return TileRef{h + TileCache::kHeader, h[0]};
    }
    TileBspView view(TileRef ref) const { return TileBspView{ref.block, ref.leaves}; }
    // Asks the cache for a tile's entry, or for words [first, first + count) of its block.
    void prefetch_tile(std::uint32_t index) const {
        const void* p = cache_ ? static_cast<const void*>(&lazy_[index]) : static_cast<const void*>(&tiles_[index]);
        _mm_prefetch(static_cast<const char*>(p), _MM_HINT_T0);
    }
    // The header of tile `index` (its leaf count, the head of its block), once its entry is cached
    // (prefetch_tile a step earlier); nothing for a lazy tile not built yet.
    void prefetch_header(std::uint32_t index) const {
        const void* p = nullptr;
        if (!cache_)
            p = pool_.data() + tiles_[index].offset;
        else
            p = lazy_[index].load(std::memory_order_relaxed);
        if (p) _mm_prefetch(static_cast<const char*>(p), _MM_HINT_T0);
    }
    void prefetch_block(TileRef ref, std::uint32_t first, std::uint32_t count) const {
        const char* a = reinterpret_cast<const char*>(ref.block + first);
        const char* b = reinterpret_cast<const char*>(ref.block + first + (count ? count : 1));
        for (const char* p = a; p < b; p += 64) _mm_prefetch(p, _MM_HINT_T0);
    }
    // Lazy tiles: whether tile `index` is built now (no query may run).
    bool built(std::uint32_t index) const { return lazy_[index].load(std::memory_order_acquire) != nullptr; }
    // Lazy tiles: builds every tile not built yet, rasterising the whole scene once (build_all).
    void build_all_tiles() const;

    // Dynamic updates. remove: the triangles `ids` (already marked absent in input.present, still
    // with the corners they were inserted with) leave every tile they were in. insert: the
    // triangles `ids` (marked present, with their new corners) enter every tile they touch.
    void remove(std::span<const std::uint32_t> ids, const SubfieldInput& input);
    void insert(std::span<const std::uint32_t> ids, const SubfieldInput& input);

    // Whole PSFs: over all tiles; lazy tiles: 0 (the TileCache counts them).
    std::size_t entries() const { return entries_; }  // triangle ids over all leaves
    std::size_t leaves() const { return leaves_; }
    std::size_t memory_bytes() const;  // lazy tiles: the tile table only
    double build_seconds() const { return build_seconds_; }

private:
    friend class TileCache;
    struct Slot {
        std::uint32_t offset = 0;  // first word of the tile's block in the pool
        std::uint32_t leaves = 0;  // 0: the tile's beam meets no triangle
    };
    // Every tile's items (sorted by id within a tile, tiles in order): items[first[t] .. first[t + 1]).
    void rasterise_all(const SubfieldInput& input, std::vector<DepthItem>& items,
                       std::vector<std::uint32_t>& first) const;
    // Lazy tiles: the header and block of tile `index` from the current triangles (new[]-allocated;
    // kEmptyTile when the beam meets nothing). Thread-safe (scratch is per thread).
    std::uint32_t* make_tile(std::uint32_t index) const;
    // Lazy tiles: a header and block from a tile's items (sorted by id).
    static std::uint32_t* make_block(std::span<const DepthItem> items, TileBspBuilder& bsp,
                                     std::vector<std::uint32_t>& block);

    // The padded prism of tile (column, row).
    Prism prism(std::uint32_t tile) const;
    Prism prism(int column, int row) const;
    // The canonical corners of triangle id.
    void corners(const SubfieldInput& input, std::uint32_t id, Vec3d* out) const;
    // Rebuilds the block of `tile` from the sorted, distinct triangle ids `ids`.
    void rebuild_tile(std::uint32_t tile, std::span<const std::uint32_t> ids, const SubfieldInput& input);
    // Sorted, distinct ids of the triangles of a tile (a straddling one sits in several leaves).
    void tile_ids(std::uint32_t tile, std::vector<std::uint32_t>& out) const;
    // Packs the blocks back to back once moved blocks have left too much of the pool unused.
    void compact();

    CanonicalFrame frame_;
    TileGrid grid_;
    int depth_ = 4;
    std::vector<Slot> tiles_;
    std::vector<std::uint32_t> room_;  // words the block of each tile may grow to in place
    std::vector<std::uint32_t> pool_;
    std::size_t garbage_ = 0;  // pool words no tile uses any more (moved blocks)
    std::size_t entries_ = 0, leaves_ = 0;
    double build_seconds_ = 0.0;

    // Lazy tiles.
    TileCache* cache_ = nullptr;
    SubfieldInput input_;
    bool stamp_ = false;  // the cache has a budget: visits stamp their tile
    std::unique_ptr<std::atomic<std::uint32_t*>[]> lazy_;
    mutable std::unique_ptr<std::uint8_t[]> built_before_;  // under the tile's build lock

    // Scratch of builds and updates.
    TileBspBuilder bsp_;
    std::vector<DepthItem> items_;
    std::vector<std::uint32_t> block_;
};

}  // namespace beamtrace::vlf
