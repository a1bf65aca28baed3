// ParallelSubfield: build (rasterise every triangle, sort the tile entries, build each tile's BSP)
// and the in-place updates of dynamic scenes.
#include "vlf/build/parallel_subfield.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "vlf/query/tile_footprint.hpp"
#include "vlf/build/tile_rasteriser.hpp"

namespace beamtrace::vlf {

namespace {

// A tile entry: the depth range of the triangle's part in the prism, widened by pad and rounded
// outwards to float, and that part's footprint on the tile's lattice.
DepthItem depth_item(std::uint32_t id, const ClippedBox& b, const FootprintLattice& lattice, double pad) {
    const double lo = b.zlo - pad, hi = b.zhi + pad;
    float flo = float(lo), fhi = float(hi);
    if (double(flo) > lo) flo = std::nextafter(flo, -INFINITY);
    if (double(fhi) < hi) fhi = std::nextafter(fhi, INFINITY);
    return DepthItem{id, flo, fhi, lattice.triangle(b.xlo, b.xhi, b.ylo, b.yhi, pad)};
}

}  // namespace

ParallelSubfield::ParallelSubfield(const CanonicalFrame& frame, const SubfieldInput& input)
    : frame_(frame), grid_(*input.grid), depth_(input.depth), bsp_(input.depth) {
    const auto start = std::chrono::steady_clock::now();
    const std::size_t n = std::size_t(grid_.n), tiles = n * n;
    tiles_.assign(tiles, Slot{});
    room_.assign(tiles, 0);
    std::vector<DepthItem> items;
    std::vector<std::uint32_t> first;
    rasterise_all(input, items, first);
    pool_.reserve(items.size() + items.size() / 2);
    for (std::size_t t = 0; t < tiles; ++t) {
        if (first[t] == first[t + 1]) continue;
        const std::uint32_t leaves =
            bsp_.build(std::span<const DepthItem>(items.data() + first[t], first[t + 1] - first[t]), block_);
        tiles_[t] = Slot{std::uint32_t(pool_.size()), leaves};
        room_[t] = std::uint32_t(block_.size());
        pool_.insert(pool_.end(), block_.begin(), block_.end());
        entries_ += TileBspView{block_.data(), leaves}.entries();
        leaves_ += leaves;
    }
    pool_.shrink_to_fit();
    build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

ParallelSubfield::ParallelSubfield(const CanonicalFrame& frame, const SubfieldInput& input, TileCache& cache)
    : frame_(frame), grid_(*input.grid), depth_(input.depth), cache_(&cache), input_(input),
      stamp_(cache.budgeted()), bsp_(input.depth) {
    const std::size_t tiles = std::size_t(grid_.n) * std::size_t(grid_.n);
    lazy_ = std::make_unique<std::atomic<std::uint32_t*>[]>(tiles);
    for (std::size_t t = 0; t < tiles; ++t) lazy_[t].store(nullptr, std::memory_order_relaxed);
    built_before_ = std::make_unique<std::uint8_t[]>(tiles);
    std::fill(built_before_.get(), built_before_.get() + tiles, std::uint8_t(0));
}

ParallelSubfield::~ParallelSubfield() {
    if (cache_) cache_->release(*this);
}

void ParallelSubfield::rasterise_all(const SubfieldInput& input, std::vector<DepthItem>& items,
                                     std::vector<std::uint32_t>& first) const {
    const std::size_t n = std::size_t(grid_.n), tiles = n * n;
    const std::size_t count = input.triangles.size();
    // Every triangle rasterised, and clipped to the prism of each tile it touches: one entry per
    // tile it really meets, with its depth range there.
    struct Entry {
        std::uint32_t tile;
        DepthItem item;
    };
    std::vector<Entry> entries;
    entries.reserve(3 * count);
    first.assign(tiles + 1, 0);
    TileRasteriser rasteriser(grid_);
    for (std::size_t id = 0; id < count; ++id) {
        if (!input.present[id]) continue;
        Vec3d v[3];
        corners(input, std::uint32_t(id), v);
        rasteriser.rasterise(v, [&](int c, int r) {
            ClippedBox clipped;
            if (!clip_to_prism(v, prism(c, r), clipped)) return;
            const auto tile = std::uint32_t(std::size_t(r) * n + std::size_t(c));
            const FootprintLattice lattice = FootprintLattice::of_tile(grid_, c, r);
            entries.push_back(Entry{tile, depth_item(std::uint32_t(id), clipped, lattice, grid_.pad)});
            ++first[tile + 1];
        });
    }
    // Counting sort by tile (ids stay ascending within a tile).
    for (std::size_t t = 0; t < tiles; ++t) first[t + 1] += first[t];
    items.resize(entries.size());
    std::vector<std::uint32_t> next(first.begin(), first.end() - 1);
    for (const Entry& e : entries) items[next[e.tile]++] = e.item;
}

std::uint32_t* ParallelSubfield::make_block(std::span<const DepthItem> items, TileBspBuilder& bsp,
                                            std::vector<std::uint32_t>& block) {
    if (items.empty()) return empty_tile_header();
    const std::uint32_t leaves = bsp.build(items, block);
    auto* h = new std::uint32_t[TileCache::kHeader + block.size()];
    h[0] = leaves;
    h[1] = 0;
    std::copy(block.begin(), block.end(), h + TileCache::kHeader);
    return h;
}

std::uint32_t* ParallelSubfield::make_tile(std::uint32_t index) const {
    // Candidates are looked up for a strip of kStrip tiles of one row at a time and kept, with their
    // canonical corners and x ranges, for the strip's other tiles: a binned stream builds the tiles
    // it reaches row by row, so one tree query and one rotation of each triangle serve several tiles.
    // The strip's key includes the tree's generation (a new field, or triangles moved, starts over).
    constexpr int kStrip = 8;
    struct Scratch {
        int depth = -1;
        std::unique_ptr<TileBspBuilder> bsp;
        std::vector<DepthItem> items;
        std::vector<std::uint32_t> block;
        std::uint64_t generation = 0;
        const ParallelSubfield* psf = nullptr;
        int row = -1, strip = -1;
        std::vector<std::uint32_t> ids;
        std::vector<Vec3d> corners;  // 3 per id
        std::vector<double> xlo, xhi;
    };
    thread_local Scratch s;
    if (!s.bsp || s.depth != depth_) {
        s.bsp = std::make_unique<TileBspBuilder>(depth_);
        s.depth = depth_;
    }
    const int n = grid_.n;
    const int c = int(index % std::uint32_t(n)), r = int(index / std::uint32_t(n));
    const Prism box = prism(c, r);
    const FootprintLattice lattice = FootprintLattice::of_tile(grid_, c, r);
    // Candidates: the triangles whose boxes may reach the padded tiles (a hair wider than the
    // rasteriser's reach, whose cells are floors of the same coordinates).
    const double margin = grid_.pad + 1e-7 * grid_.radius;
    if (s.generation != cache_->generation() || s.psf != this || s.row != r || s.strip != c / kStrip) {
        s.generation = cache_->generation();
        s.psf = this;
        s.row = r;
        s.strip = c / kStrip;
        s.ids.clear();
        s.corners.clear();
        s.xlo.clear();
        s.xhi.clear();
        const int c0 = s.strip * kStrip, c1 = std::min(n - 1, c0 + kStrip - 1);
        cache_->tree.query(frame_, grid_.centre, prism(c0, r).x0 - margin, prism(c1, r).x1 + margin, box.y0 - margin,
                           box.y1 + margin, [&](std::uint32_t id) {
                               Vec3d v[3];
                               corners(input_, id, v);
                               s.ids.push_back(id);
                               s.corners.insert(s.corners.end(), v, v + 3);
                               s.xlo.push_back(std::min({v[0].x, v[1].x, v[2].x}));
                               s.xhi.push_back(std::max({v[0].x, v[1].x, v[2].x}));
                           });
    }
    s.items.clear();
    for (std::size_t k = 0; k < s.ids.size(); ++k) {
        // Outside the tile's reach in x (TileRasteriser::touches would say no), or removed since.
        if (s.xhi[k] + margin < box.x0 || s.xlo[k] - margin > box.x1 || !input_.present[s.ids[k]]) continue;
        const Vec3d* v = &s.corners[3 * k];
        if (!TileRasteriser::touches(grid_, v, c, r)) continue;
        ClippedBox clipped;
        if (clip_to_prism(v, box, clipped)) s.items.push_back(depth_item(s.ids[k], clipped, lattice, grid_.pad));
    }
    return make_block(s.items, *s.bsp, s.block);
}

void ParallelSubfield::build_all_tiles() const {
    TileBspBuilder bsp(depth_);
    std::vector<std::uint32_t> block;
    std::vector<DepthItem> items;
    std::vector<std::uint32_t> first;
    rasterise_all(input_, items, first);
    const std::size_t tiles = std::size_t(grid_.n) * std::size_t(grid_.n);
    for (std::size_t t = 0; t < tiles; ++t) {
        if (built(std::uint32_t(t))) continue;
        cache_->adopt(*this, std::uint32_t(t), [&] {
            return make_block(std::span<const DepthItem>(items.data() + first[t], first[t + 1] - first[t]), bsp,
                              block);
        });
    }
}

Prism ParallelSubfield::prism(std::uint32_t tile) const {
    return prism(int(tile % std::uint32_t(grid_.n)), int(tile / std::uint32_t(grid_.n)));
}

Prism ParallelSubfield::prism(int c, int r) const {
    const double x0 = grid_.edge(c), y0 = grid_.edge(r), pad = grid_.pad;
    return Prism{x0 - pad, x0 + grid_.h + pad, y0 - pad, y0 + grid_.h + pad};
}

void ParallelSubfield::corners(const SubfieldInput& input, std::uint32_t id, Vec3d* out) const {
    const Triangle& t = input.triangles[id];
    out[0] = frame_.point(t.v0, grid_);
    out[1] = frame_.point(t.v1, grid_);
    out[2] = frame_.point(t.v2, grid_);
}

void ParallelSubfield::tile_ids(std::uint32_t tile, std::vector<std::uint32_t>& out) const {
    out.clear();
    const Slot ref = tiles_[tile];
    if (ref.leaves == 0) return;
    const TileBspView v{pool_.data() + ref.offset, ref.leaves};
    const PackedIds ids = v.ids();
    for (std::uint32_t k = 0; k < v.entries(); ++k) out.push_back(ids[k]);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
}

void ParallelSubfield::rebuild_tile(std::uint32_t tile, std::span<const std::uint32_t> ids,
                                    const SubfieldInput& input) {
    Slot& ref = tiles_[tile];
    if (ref.leaves > 0) {
        const TileBspView old{pool_.data() + ref.offset, ref.leaves};
        entries_ -= old.entries();
        leaves_ -= ref.leaves;
    }
    const Prism box = prism(tile);
    const FootprintLattice lattice =
        FootprintLattice::of_tile(grid_, int(tile % std::uint32_t(grid_.n)), int(tile / std::uint32_t(grid_.n)));
    items_.clear();
    for (std::uint32_t id : ids) {
        Vec3d v[3];
        corners(input, id, v);
        ClippedBox clipped;
        if (clip_to_prism(v, box, clipped)) items_.push_back(depth_item(id, clipped, lattice, grid_.pad));
    }
    if (items_.empty()) {
        ref.leaves = 0;  // keeps its offset and room for a later insertion
        return;
    }
    const std::uint32_t leaves = bsp_.build(items_, block_);
    if (block_.size() <= room_[tile] && room_[tile] > 0) {
        std::copy(block_.begin(), block_.end(), pool_.begin() + std::ptrdiff_t(ref.offset));
    } else {
        garbage_ += room_[tile];
        ref.offset = std::uint32_t(pool_.size());
        room_[tile] = std::uint32_t(block_.size());
        pool_.insert(pool_.end(), block_.begin(), block_.end());
    }
    ref.leaves = leaves;
    entries_ += TileBspView{block_.data(), leaves}.entries();
    leaves_ += leaves;
}

void ParallelSubfield::remove(std::span<const std::uint32_t> ids, const SubfieldInput& input) {
    const std::uint32_t n = std::uint32_t(grid_.n);
    std::vector<std::uint32_t> touched;
    TileRasteriser rasteriser(grid_);
    for (std::uint32_t id : ids) {
        Vec3d v[3];
        corners(input, id, v);
        rasteriser.rasterise(v, [&](int c, int r) { touched.push_back(std::uint32_t(r) * n + std::uint32_t(c)); });
    }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    if (cache_) {  // lazy tiles: built ones rebuilt from the current triangles, the others later
        for (std::uint32_t tile : touched)
            if (built(tile)) cache_->rebuild_now(*this, tile);
        return;
    }
    std::vector<std::uint32_t> current;
    for (std::uint32_t tile : touched) {
        if (tiles_[tile].leaves == 0) continue;
        tile_ids(tile, current);
        std::erase_if(current, [&](std::uint32_t id) { return !input.present[id]; });
        rebuild_tile(tile, current, input);
    }
    compact();
}

void ParallelSubfield::insert(std::span<const std::uint32_t> ids, const SubfieldInput& input) {
    const std::uint64_t n = std::uint64_t(grid_.n);
    std::vector<std::uint64_t> pairs;
    TileRasteriser rasteriser(grid_);
    for (std::uint32_t id : ids) {
        if (!input.present[id]) continue;
        Vec3d v[3];
        corners(input, id, v);
        rasteriser.rasterise(
            v, [&](int c, int r) { pairs.push_back(((std::uint64_t(r) * n + std::uint64_t(c)) << 32) | id); });
    }
    std::sort(pairs.begin(), pairs.end());
    if (cache_) {  // lazy tiles: built ones rebuilt from the current triangles, the others later
        for (std::size_t b = 0; b < pairs.size(); ++b) {
            const auto tile = std::uint32_t(pairs[b] >> 32);
            if ((b == 0 || tile != std::uint32_t(pairs[b - 1] >> 32)) && built(tile)) cache_->rebuild_now(*this, tile);
        }
        return;
    }
    std::vector<std::uint32_t> current;
    for (std::size_t b = 0; b < pairs.size();) {
        const auto tile = std::uint32_t(pairs[b] >> 32);
        std::size_t e = b;
        tile_ids(tile, current);
        for (; e < pairs.size() && (pairs[e] >> 32) == tile; ++e) current.push_back(std::uint32_t(pairs[e]));
        std::sort(current.begin(), current.end());
        current.erase(std::unique(current.begin(), current.end()), current.end());
        rebuild_tile(tile, current, input);
        b = e;
    }
    compact();
}

void ParallelSubfield::compact() {
    if (garbage_ * 2 <= pool_.size()) return;
    std::vector<std::uint32_t> packed;
    packed.reserve(pool_.size() - garbage_);
    for (std::size_t t = 0; t < tiles_.size(); ++t) {
        Slot& ref = tiles_[t];
        if (ref.leaves == 0) {
            ref.offset = 0;
            room_[t] = 0;
            continue;
        }
        const std::uint32_t words = TileBspView{pool_.data() + ref.offset, ref.leaves}.words();
        const auto offset = std::uint32_t(packed.size());
        packed.insert(packed.end(), pool_.begin() + std::ptrdiff_t(ref.offset),
                      pool_.begin() + std::ptrdiff_t(ref.offset + words));
        ref.offset = offset;
        room_[t] = words;
    }
    pool_ = std::move(packed);
    garbage_ = 0;
}

std::size_t ParallelSubfield::memory_bytes() const {
    const std::size_t lazy_tiles = cache_ ? std::size_t(grid_.n) * std::size_t(grid_.n) : 0;
    return sizeof(*this) + tiles_.capacity() * sizeof(Slot) + room_.capacity() * sizeof(std::uint32_t) +
           pool_.capacity() * sizeof(std::uint32_t) + lazy_tiles * (sizeof(std::atomic<std::uint32_t*>) + 1);
}

}  // namespace beamtrace::vlf
