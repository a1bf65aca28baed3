#pragma once
// TileCache: the lazily built tiles of a field's parallel subfields (parallel_subfield.hpp), their
// memory and, under a memory budget, their eviction.
//
// A tile's block is built the first time a ray reaches it (under one of a few striped locks, so two
// threads never build the same tile) and published through the tile's atomic pointer; once built,
// readers take the pointer without a lock. Blocks live on the heap behind a two-word header:
// [leaves][last use], the block (tile_bsp.hpp) follows.
//
// With a budget (VlfOptions::memory_budget_bytes), building past it evicts the least recently used
// tiles: every visit of a tile stamps its header with the cache's clock (a store only when the stamp
// changes), and an eviction round takes the tiles with the oldest stamps until the tiles are back at
// 7/8 of their share of the budget. An evicted tile's pointer is cleared at once (the next ray
// rebuilds it) but its block is freed only when no reader can still hold it: epoch-based
// reclamation. Every query runs inside a ReadGuard, which holds a reader slot with the epoch the
// reader last saw; a reader that holds no block pointer (between the PSFs of a binned stream, every
// 64 packets of an ordered one) reports a quiescent state, which moves its slot to the current
// epoch. A retired block is freed once every active slot has seen its retirement epoch. The read
// path pays one relaxed load and, at most once per clock tick per tile, one store; a query pays a
// slot claim (one compare-and-swap) and a fence per quiescent state. The cost is memory: retired
// blocks wait for the readers' next quiescent state (at most about one PSF's worth of tiles).
// Without a budget nothing is stamped, guarded or evicted.
#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <vector>

#include "vlf/build/triangle_box_tree.hpp"

namespace beamtrace::vlf {

class ParallelSubfield;

// The header every empty lazy tile points at (leaves 0; never written).
std::uint32_t* empty_tile_header();

struct TileCacheStats {
    std::size_t tiles_built = 0, tiles_evicted = 0, resident_tiles = 0;
    std::size_t tile_bytes = 0;      // blocks of resident tiles, and retired ones not yet freed
    std::size_t peak_tile_bytes = 0; // the most tile_bytes ever was
    std::size_t entries = 0, leaves = 0;  // over resident tiles
    double build_seconds = 0.0, rebuild_seconds = 0.0;  // every tile build; those of evicted tiles
};

class TileCache {
public:
    static constexpr std::uint32_t kHeader = 2;  // words before a block: leaves, last use
    // budget_bytes: what resident and retired blocks may hold (0 = unbounded).
    explicit TileCache(std::size_t budget_bytes);
    ~TileCache();
    TileCache(const TileCache&) = delete;
    TileCache& operator=(const TileCache&) = delete;

    bool budgeted() const { return budget_ > 0; }
    std::uint32_t clock() const { return clock_.load(std::memory_order_relaxed); }

    // Tile `index` of psf: built now unless another thread did first. Returns its header.
    std::uint32_t* build(const ParallelSubfield& psf, std::uint32_t index);
    // Publishes make() (a header from ParallelSubfield::make_block) as tile `index` of psf unless it
    // is built by then (build_all).
    template <class Make>
    void adopt(const ParallelSubfield& psf, std::uint32_t index, Make&& make);
    // Replaces (or builds) the block of a built tile after a dynamic update; no query may run.
    void rebuild_now(const ParallelSubfield& psf, std::uint32_t index);
    // Frees every block of psf (its destruction); no query may run.
    void release(const ParallelSubfield& psf);
    // Frees every resident block (before the PSFs go: the field's destruction).
    void release_all();

    // The tree lazy builds query (set by the field, refit after updates through refit()), and a
    // number no other tree state of any cache had: builds keep per-thread candidates under it.
    TriangleBoxTree tree;
    void refit(std::span<const Triangle> triangles, std::span<const std::uint8_t> present);
    std::uint64_t generation() const { return generation_; }

    // ---- readers ----
    class ReadGuard {
    public:
        explicit ReadGuard(TileCache& cache);
        ~ReadGuard();
        ReadGuard(const ReadGuard&) = delete;
        ReadGuard& operator=(const ReadGuard&) = delete;

    private:
        friend class TileCache;
        TileCache* cache_ = nullptr;
        std::atomic<std::uint64_t>* slot_ = nullptr;  // nullptr: no budget, or nested in a guard of this cache
        const ReadGuard* outer_ = nullptr;
    };
    // The calling thread holds no block pointer of this cache (see above); a no-op without a budget
    // or inside a nested guard.
    void quiescent();

    TileCacheStats stats() const;
    std::size_t memory_bytes() const;  // the tree and the tile blocks (resident and retired)

private:
    struct Resident {
        const ParallelSubfield* psf;
        std::uint32_t index, bytes;
    };
    struct Retired {
        std::uint32_t* block;
        std::uint64_t epoch;
        std::size_t bytes;
    };
    static constexpr std::size_t kStripes = 1024, kSlots = 256;

    std::mutex& stripe(const ParallelSubfield& psf, std::uint32_t index) const;
    // Under the tile's stripe: counts and publishes a new header h, built in `seconds`.
    void publish(const ParallelSubfield& psf, std::uint32_t index, std::uint32_t* h, double seconds);
    void evict_locked(std::size_t keep_last);
    void reclaim_locked();
    std::uint64_t oldest_active_epoch() const;
    static bool is_built(const ParallelSubfield& psf, std::uint32_t index);
    void account(std::int64_t bytes);  // to bytes_ (and peak_)

    std::size_t budget_;
    std::uint64_t generation_ = 0;
    std::atomic<std::uint32_t> clock_{1};
    std::atomic<std::uint64_t> epoch_{1};
    std::unique_ptr<std::atomic<std::uint64_t>[]> slots_;  // 0: free
    std::unique_ptr<std::mutex[]> stripes_;
    mutable std::mutex lru_;  // resident_, retired_
    std::vector<Resident> resident_;
    std::deque<Retired> retired_;  // in retirement order (ascending epochs)
    // live_: blocks of resident tiles (what the budget bounds); bytes_: those and retired ones.
    std::atomic<std::size_t> live_{0}, bytes_{0}, peak_{0}, built_{0}, evicted_{0}, entries_{0}, leaves_{0};
    std::atomic<std::int64_t> build_ns_{0}, rebuild_ns_{0};
};

template <class Make>
void TileCache::adopt(const ParallelSubfield& psf, std::uint32_t index, Make&& make) {
    std::lock_guard<std::mutex> lock(stripe(psf, index));
    if (is_built(psf, index)) return;
    publish(psf, index, make(), 0.0);
}

}  // namespace beamtrace::vlf
