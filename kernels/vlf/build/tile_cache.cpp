// TileCache: lazy tile builds, their accounting, LRU eviction under a budget and epoch-based
// reclamation of evicted blocks (see tile_cache.hpp).
#include "vlf/build/tile_cache.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

#include "vlf/build/parallel_subfield.hpp"

namespace beamtrace::vlf {

namespace {

std::uint32_t empty_header[TileCache::kHeader] = {0, 0};

// The innermost guard of this thread (guards of several caches may nest).
thread_local const TileCache::ReadGuard* innermost = nullptr;

// Heap bytes of a block with its header (the allocator's own word included).
std::size_t block_bytes(const std::uint32_t* h) {
    const TileBspView v{h + TileCache::kHeader, h[0]};
    return (TileCache::kHeader + v.words()) * sizeof(std::uint32_t) + 16;
}

}  // namespace

static std::atomic<std::uint64_t> generations{0};

std::uint32_t* empty_tile_header() { return empty_header; }

void TileCache::refit(std::span<const Triangle> triangles, std::span<const std::uint8_t> present) {
    tree.build(triangles, present);
    generation_ = generations.fetch_add(1) + 1;
}

TileCache::TileCache(std::size_t budget_bytes)
    : budget_(budget_bytes),
      slots_(std::make_unique<std::atomic<std::uint64_t>[]>(kSlots)),
      stripes_(std::make_unique<std::mutex[]>(kStripes)) {
    for (std::size_t i = 0; i < kSlots; ++i) slots_[i].store(0, std::memory_order_relaxed);
}

TileCache::~TileCache() {
    for (const Retired& r : retired_) delete[] r.block;
}

std::mutex& TileCache::stripe(const ParallelSubfield& psf, std::uint32_t index) const {
    const auto key = std::uint64_t(reinterpret_cast<std::uintptr_t>(&psf)) * 0x9E3779B97F4A7C15ull + index;
    return stripes_[(key ^ (key >> 29)) % kStripes];
}

bool TileCache::is_built(const ParallelSubfield& psf, std::uint32_t index) {
    return psf.lazy_[index].load(std::memory_order_acquire) != nullptr;
}

void TileCache::account(std::int64_t bytes) {
    const std::size_t now = bytes_.fetch_add(std::size_t(bytes), std::memory_order_relaxed) + std::size_t(bytes);
    std::size_t peak = peak_.load(std::memory_order_relaxed);
    while (now > peak && !peak_.compare_exchange_weak(peak, now, std::memory_order_relaxed)) {
    }
}

std::uint32_t* TileCache::build(const ParallelSubfield& psf, std::uint32_t index) {
    std::lock_guard<std::mutex> lock(stripe(psf, index));
    if (std::uint32_t* h = psf.lazy_[index].load(std::memory_order_acquire)) return h;
    const auto start = std::chrono::steady_clock::now();
    std::uint32_t* h = psf.make_tile(index);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    publish(psf, index, h, seconds);
    return h;
}

void TileCache::publish(const ParallelSubfield& psf, std::uint32_t index, std::uint32_t* h, double seconds) {
    const auto ns = std::int64_t(seconds * 1e9);
    built_.fetch_add(1, std::memory_order_relaxed);
    build_ns_.fetch_add(ns, std::memory_order_relaxed);
    if (psf.built_before_[index]) rebuild_ns_.fetch_add(ns, std::memory_order_relaxed);
    psf.built_before_[index] = 1;
    if (h[0] == 0) {  // empty: nothing to hold or evict
        psf.lazy_[index].store(h, std::memory_order_release);
        return;
    }
    h[1] = clock();
    const std::size_t bytes = block_bytes(h);
    const TileBspView v{h + kHeader, h[0]};
    entries_.fetch_add(v.entries(), std::memory_order_relaxed);
    leaves_.fetch_add(h[0], std::memory_order_relaxed);
    account(std::int64_t(bytes));
    const std::size_t live = live_.fetch_add(bytes, std::memory_order_relaxed) + bytes;
    psf.lazy_[index].store(h, std::memory_order_release);
    std::lock_guard<std::mutex> lock(lru_);
    resident_.push_back(Resident{&psf, index, std::uint32_t(bytes)});
    if (budget_ && live > budget_) evict_locked(1);
}

void TileCache::rebuild_now(const ParallelSubfield& psf, std::uint32_t index) {
    std::uint32_t* old = psf.lazy_[index].load(std::memory_order_acquire);
    if (old && old[0]) {
        std::lock_guard<std::mutex> lock(lru_);
        auto it = std::find_if(resident_.begin(), resident_.end(),
                               [&](const Resident& r) { return r.psf == &psf && r.index == index; });
        if (it != resident_.end()) {
            *it = resident_.back();
            resident_.pop_back();
        }
        const TileBspView v{old + kHeader, old[0]};
        entries_.fetch_sub(v.entries(), std::memory_order_relaxed);
        leaves_.fetch_sub(old[0], std::memory_order_relaxed);
        account(-std::int64_t(block_bytes(old)));
        live_.fetch_sub(block_bytes(old), std::memory_order_relaxed);
        delete[] old;
    }
    psf.lazy_[index].store(nullptr, std::memory_order_release);
    build(psf, index);
}

void TileCache::release(const ParallelSubfield& psf) {
    const std::size_t tiles = std::size_t(psf.grid_.n) * std::size_t(psf.grid_.n);
    bool held = false;
    for (std::size_t t = 0; t < tiles && !held; ++t) {
        const std::uint32_t* h = psf.lazy_[t].load(std::memory_order_relaxed);
        held = h && h[0];
    }
    if (!held) return;  // release_all ran first (the field's destruction), or nothing was built
    std::lock_guard<std::mutex> lock(lru_);
    std::erase_if(resident_, [&](const Resident& r) {
        if (r.psf != &psf) return false;
        std::uint32_t* h = psf.lazy_[r.index].load(std::memory_order_relaxed);
        const TileBspView v{h + kHeader, h[0]};
        entries_.fetch_sub(v.entries(), std::memory_order_relaxed);
        leaves_.fetch_sub(h[0], std::memory_order_relaxed);
        account(-std::int64_t(r.bytes));
        live_.fetch_sub(r.bytes, std::memory_order_relaxed);
        delete[] h;
        psf.lazy_[r.index].store(nullptr, std::memory_order_relaxed);
        return true;
    });
}

void TileCache::release_all() {
    std::lock_guard<std::mutex> lock(lru_);
    for (const Resident& r : resident_) {
        delete[] r.psf->lazy_[r.index].load(std::memory_order_relaxed);
        r.psf->lazy_[r.index].store(nullptr, std::memory_order_relaxed);
    }
    resident_.clear();
    live_.store(0);
    entries_.store(0);
    leaves_.store(0);
}

void TileCache::evict_locked(std::size_t keep_last) {
    reclaim_locked();
    // Down to 7/8 of the budget: room for the retired blocks until readers let them go.
    const std::size_t target = budget_ - budget_ / 8;
    const std::size_t now = live_.load(std::memory_order_relaxed);
    if (now <= target || resident_.size() <= keep_last) return;
    std::size_t excess = now - target;
    // The oldest stamps first (ties: the earlier built), never the newest keep_last tiles.
    const std::size_t candidates = resident_.size() - keep_last;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> order(candidates);
    for (std::size_t k = 0; k < candidates; ++k) {
        const Resident& r = resident_[k];
        std::uint32_t* h = r.psf->lazy_[r.index].load(std::memory_order_relaxed);
        order[k] = {std::atomic_ref<std::uint32_t>(h[1]).load(std::memory_order_relaxed), std::uint32_t(k)};
    }
    std::sort(order.begin(), order.end());
    std::vector<std::uint8_t> gone(resident_.size(), 0);
    const std::uint64_t epoch = epoch_.fetch_add(1, std::memory_order_seq_cst) + 1;
    std::size_t evicted = 0;
    for (const auto& [stamp, k] : order) {
        if (excess == 0) break;
        const Resident& r = resident_[k];
        std::uint32_t* h = r.psf->lazy_[r.index].load(std::memory_order_relaxed);
        r.psf->lazy_[r.index].store(nullptr, std::memory_order_seq_cst);
        const TileBspView v{h + kHeader, h[0]};
        entries_.fetch_sub(v.entries(), std::memory_order_relaxed);
        leaves_.fetch_sub(h[0], std::memory_order_relaxed);
        retired_.push_back(Retired{h, epoch, r.bytes});
        live_.fetch_sub(r.bytes, std::memory_order_relaxed);
        gone[k] = 1;
        excess -= std::min<std::size_t>(excess, r.bytes);
        ++evicted;
    }
    evicted_.fetch_add(evicted, std::memory_order_relaxed);
    std::size_t out = 0;
    for (std::size_t k = 0; k < resident_.size(); ++k)
        if (!gone[k]) resident_[out++] = resident_[k];
    resident_.resize(out);
    // The unlinks above happen before the epoch advances past `epoch` for any reader.
    epoch_.fetch_add(1, std::memory_order_seq_cst);
    std::atomic_thread_fence(std::memory_order_seq_cst);
    reclaim_locked();
}

std::uint64_t TileCache::oldest_active_epoch() const {
    std::atomic_thread_fence(std::memory_order_seq_cst);
    std::uint64_t oldest = ~std::uint64_t(0);
    for (std::size_t i = 0; i < kSlots; ++i) {
        const std::uint64_t e = slots_[i].load(std::memory_order_seq_cst);
        if (e != 0) oldest = std::min(oldest, e);
    }
    return oldest;
}

void TileCache::reclaim_locked() {
    if (retired_.empty()) return;
    const std::uint64_t oldest = oldest_active_epoch();
    // Every active reader entered after these retirements: nobody holds them.
    while (!retired_.empty() && retired_.front().epoch < oldest) {
        delete[] retired_.front().block;
        account(-std::int64_t(retired_.front().bytes));
        retired_.pop_front();
    }
}

TileCache::ReadGuard::ReadGuard(TileCache& cache) : outer_(innermost) {
    if (!cache.budgeted()) return;
    innermost = this;
    cache_ = &cache;
    for (const ReadGuard* g = outer_; g; g = g->outer_)
        if (g->cache_ == &cache) return;  // nested: the outer guard's slot covers this call
    for (;;) {
        for (std::size_t i = 0; i < kSlots; ++i) {
            std::uint64_t free = 0;
            if (cache.slots_[i].load(std::memory_order_relaxed) == 0 &&
                cache.slots_[i].compare_exchange_strong(free, cache.epoch_.load(std::memory_order_seq_cst),
                                                        std::memory_order_seq_cst)) {
                slot_ = &cache.slots_[i];
                std::atomic_thread_fence(std::memory_order_seq_cst);
                cache.clock_.fetch_add(1, std::memory_order_relaxed);
                return;
            }
        }
        std::this_thread::yield();  // more than kSlots queries at once: wait for one to end
    }
}

TileCache::ReadGuard::~ReadGuard() {
    if (!cache_) return;
    innermost = outer_;
    if (!slot_) return;
    slot_->store(0, std::memory_order_seq_cst);
    std::unique_lock<std::mutex> lock(cache_->lru_, std::try_to_lock);
    if (lock.owns_lock()) cache_->reclaim_locked();
}

void TileCache::quiescent() {
    if (!budget_) return;
    const ReadGuard* g = innermost;
    if (!g || g->cache_ != this || !g->slot_) return;  // not the guard that owns this thread's slot
    g->slot_->store(epoch_.load(std::memory_order_seq_cst), std::memory_order_seq_cst);
    std::atomic_thread_fence(std::memory_order_seq_cst);
    clock_.fetch_add(1, std::memory_order_relaxed);
    std::unique_lock<std::mutex> lock(lru_, std::try_to_lock);
    if (lock.owns_lock()) reclaim_locked();
}

TileCacheStats TileCache::stats() const {
    TileCacheStats s;
    s.tiles_built = built_.load();
    s.tiles_evicted = evicted_.load();
    s.tile_bytes = bytes_.load();
    s.peak_tile_bytes = peak_.load();
    s.entries = entries_.load();
    s.leaves = leaves_.load();
    s.build_seconds = double(build_ns_.load()) * 1e-9;
    s.rebuild_seconds = double(rebuild_ns_.load()) * 1e-9;
    std::lock_guard<std::mutex> lock(lru_);
    s.resident_tiles = resident_.size();
    return s;
}

std::size_t TileCache::memory_bytes() const { return tree.memory_bytes() + bytes_.load(); }

}  // namespace beamtrace::vlf
