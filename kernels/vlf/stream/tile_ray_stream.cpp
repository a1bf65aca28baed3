// TileRayBins: one-tile rays of binned occlusion streams, binned per PSF, ordered by tile and traced
// in batches of 16 (see tile_ray_stream.hpp).
#include "vlf/stream/tile_ray_stream.hpp"

#include <algorithm>
#include <utility>

#include <immintrin.h>

#include "vlf/query/tile_walk.hpp"
#include "vlf/build/tile_cache.hpp"

namespace beamtrace::vlf {

TileRayLease::TileRayLease(const VisibilityField::Impl& f) : field_(f) {
    {
        std::lock_guard<std::mutex> lock(f.stream_bins_lock);
        if (!f.stream_bins.empty()) {
            bins_ = std::move(f.stream_bins.back());
            f.stream_bins.pop_back();
        }
    }
    if (!bins_) bins_ = std::make_unique<TileRayBins>();
}

TileRayLease::~TileRayLease() {
    std::lock_guard<std::mutex> lock(field_.stream_bins_lock);
    field_.stream_bins.push_back(std::move(bins_));
}

std::size_t TileRayBins::bytes() const {
    return (pool_size_ + 16) * sizeof(TileRay) + batches_.capacity() * sizeof(Batch) +
           (link_.capacity() + last_.capacity() + fill_.capacity() + count_.capacity()) * sizeof(std::uint32_t);
}

void TileRayBins::begin(std::size_t psfs, std::uint32_t tiles_per_side, std::size_t rays) {
    // Blocks of 2^shift_ tiles a side, halved until a PSF's rays spread over enough of them to give
    // about kRaysPerBlock a bin (the rays' tiles then fit in the caches with room to spare).
    const std::size_t wanted = std::max<std::size_t>(1, rays / std::max<std::size_t>(1, psfs) / kRaysPerBlock);
    shift_ = 0;
    while ((1u << shift_) < tiles_per_side) ++shift_;
    auto side = [&](std::uint32_t s) { return (tiles_per_side + (1u << s) - 1u) >> s; };
    while (shift_ > 0 && std::size_t(side(shift_)) * side(shift_) < wanted) --shift_;
    blocks_side_ = side(shift_);
    const std::size_t bins = psfs * blocks_side_ * blocks_side_;
    // Every chunk but a bin's newest is full.
    const std::size_t chunks = (rays + kChunk - 1) / kChunk + std::min(bins, rays);
    if (pool_size_ < chunks * kChunk) {
        pool_size_ = chunks * kChunk;
        pool_.reset(new TileRay[pool_size_ + 16]);  // + 16: read ahead; pages touched as they fill
    }
    chunks_ = 0;
    link_.resize(chunks);
    last_.assign(bins, kNone);
    fill_.assign(bins, 0);
    count_.assign(psfs, 0);
}

std::uint32_t TileRayBins::take(const VisibilityField::Impl& f, const Packet16& p, const PacketLookup& l,
                                std::uint32_t slot0, VlfMode mode) {
    const std::uint32_t lanes = mode == VlfMode::exact ? l.one_tile : l.valid;
    TileRay* to[16];
    for (std::uint32_t m = lanes; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        const std::uint32_t psf = l.psf[i];
        const std::uint32_t bin = (psf * blocks_side_ + (std::uint32_t(l.row[i]) >> shift_)) * blocks_side_ +
                                  (std::uint32_t(l.column[i]) >> shift_);
        if (last_[bin] == kNone || fill_[bin] == kChunk) {
            link_[chunks_] = last_[bin];
            last_[bin] = chunks_++;
            fill_[bin] = 0;
        }
        to[i] = &pool_[std::size_t(last_[bin]) * kChunk + fill_[bin]++];
        ++count_[psf];
    }
    f.simd->store_tile_rays(l, p, lanes, std::uint32_t(f.grid.n), slot0, to);
    return lanes;
}

void TileRayBins::trace(const VisibilityField::Impl& f, std::span<std::uint32_t> occluded) {
    const std::size_t blocks = std::size_t(blocks_side_) * blocks_side_;
    for (std::size_t psf = 0; psf < count_.size(); ++psf) {
        if (count_[psf] == 0) continue;
        // The PSF's bins block by block (row-major), each bin's chunks newest first, 16 rays a batch.
        batches_.clear();
        for (std::size_t bin = psf * blocks; bin < (psf + 1) * blocks; ++bin)
            for (std::uint32_t c = last_[bin]; c != kNone; c = link_[c]) {
                const std::uint32_t size = c == last_[bin] ? fill_[bin] : kChunk;
                const TileRay* rays = &pool_[std::size_t(c) * kChunk];
                for (std::uint32_t k = 0; k < size; k += 16) batches_.push_back({rays + k, std::min(16u, size - k)});
            }
        f.quiescent();  // no tile held between PSFs
        trace_psf(f, f.psf(std::uint32_t(psf)), batches_, occluded);
    }
}

void TileRayBins::trace_psf(const VisibilityField::Impl& f, const ParallelSubfield& psf, std::span<const Batch> list,
                            std::span<std::uint32_t> occluded) {
    const std::size_t batches = list.size();
    const Triangle* triangles = f.triangles.data();
    const VlfKernels& kernels = *f.simd;
    // Batch b's rays as rays[first .. end).
    struct Range {
        const TileRay* rays;
        std::size_t first, end;
    };
    auto range = [&](std::size_t b) { return Range{list[b].rays, 0, list[b].count}; };
    // Stage 0: the rays' records (written by streaming stores: in memory, not in the caches).
    auto request_rays = [&](std::size_t b) {
        const char* a = reinterpret_cast<const char*>(list[b].rays);
        for (std::uint32_t k = 0; k < list[b].count; ++k) _mm_prefetch(a + 64 * k, _MM_HINT_T2);
    };
    // Stage 1: the tile entries.
    auto request_entries = [&](std::size_t b) {
        const auto [rays, first, end] = range(b);
        for (std::size_t i = first; i < end; ++i) psf.prefetch_tile(rays[i].tile);
    };
    // Stage 1b: each tile's header (its pointer is cached by then).
    auto request_headers = [&](std::size_t b) {
        const auto [rays, first, end] = range(b);
        for (std::size_t i = first; i < end; ++i)
            if (i == first || rays[i].tile != rays[i - 1].tile) psf.prefetch_header(rays[i].tile);
    };
    // Stage 2: the splits and leaf ends at the head of each block.
    auto request_heads = [&](std::size_t b) {
        const auto [rays, first, end] = range(b);
        for (std::size_t i = first; i < end; ++i) {
            if (i > first && rays[i].tile == rays[i - 1].tile) continue;
            const TileRef ref = psf.tile(rays[i].tile);
            if (ref.leaves) psf.prefetch_block(ref, 0, 2 * ref.leaves - 1);
        }
    };
    struct Stage {
        TileRayBatch batch;
        const std::uint32_t* groups[16];
        const std::uint32_t* footprints[16];
        PackedIds ids[16];
        std::uint32_t first[16], count[16];
        bool distinct[16];
        std::uint32_t pairs = 0;
    };
    Stage ring[8];
    // Stage 3: each ray's leaves, and the footprints and ids of their entries requested.
    auto request_entries_of_leaves = [&](std::size_t b) {
        const auto [rays, first, end] = range(b);
        Stage& s = ring[b % 8];
        for (std::size_t i = first; i < end; ++i) {
            const TileRay& r = rays[i];
            const std::size_t lane = i - first;
            s.count[lane] = 0;
            const TileRef ref = psf.tile(r.tile);
            if (ref.leaves == 0) continue;
            const TileBspView bsp = psf.view(ref);
            std::uint32_t j0 = 0, j1 = 0;
            if (ref.leaves > 1) {
                j0 = bsp.leaf(r.z0);
                j1 = bsp.leaf(r.z1);
                if (j0 > j1) std::swap(j0, j1);
            }
            const std::uint32_t e0 = bsp.begin(j0), count = bsp.end(j1) - e0;
            s.groups[lane] = bsp.groups();
            s.footprints[lane] = bsp.footprints();
            s.ids[lane] = bsp.ids();
            s.first[lane] = e0;
            s.count[lane] = count;
            s.distinct[lane] = j0 == j1;
            // A short run: its footprints and ids; a long one: its groups' union footprints.
            const std::uint32_t g0 = e0 / 16, g1 = (e0 + count + 15) / 16;
            if (s.groups[lane] == nullptr || g1 - g0 <= kDirectGroups) {
                const char* a = reinterpret_cast<const char*>(s.footprints[lane] + e0);
                const char* c = reinterpret_cast<const char*>((s.ids[lane] + e0).bytes);
                for (std::uint32_t k = 0; k < 4 * count + 63; k += 64) _mm_prefetch(a + k, _MM_HINT_T0);
                for (std::uint32_t k = 0; k < 3 * count + 63; k += 64) _mm_prefetch(c + k, _MM_HINT_T0);
            } else {
                const char* a = reinterpret_cast<const char*>(s.groups[lane] + g0);
                for (std::uint32_t k = 0; k < 4 * (g1 - g0) + 63; k += 64) _mm_prefetch(a + k, _MM_HINT_T0);
            }
        }
    };
    // Stage 4: for long runs, the entries of the groups whose union meets the ray requested.
    std::vector<std::uint32_t>& passing = passing_;
    auto request_groups = [&](std::size_t b) {
        const auto [rays, first, end] = range(b);
        const Stage& s = ring[b % 8];
        for (std::size_t i = first; i < end; ++i) {
            const std::size_t lane = i - first;
            const std::uint32_t e0 = s.first[lane], count = s.count[lane];
            const std::uint32_t g0 = e0 / 16, g1 = (e0 + count + 15) / 16;
            if (count == 0 || s.groups[lane] == nullptr || g1 - g0 <= kDirectGroups) continue;
            if (passing.size() < g1 - g0 + 16) passing.resize(2 * (g1 - g0 + 16));
            const std::uint32_t n =
                kernels.scan_footprints(s.groups[lane] + g0, g1 - g0, rays[i].footprint, passing.data());
            for (std::uint32_t k = 0; k < n; ++k) {
                const std::uint32_t g = g0 + passing[k];
                _mm_prefetch(reinterpret_cast<const char*>(s.footprints[lane] + 16 * g), _MM_HINT_T0);
                const char* c = reinterpret_cast<const char*>((s.ids[lane] + 16 * g).bytes);
                _mm_prefetch(c, _MM_HINT_T0);
                _mm_prefetch(c + 47, _MM_HINT_T0);
            }
        }
    };
    // Stage 5: the candidates, and their triangles requested.
    auto candidates = [&](std::size_t b) {
        const auto [rays, first, end] = range(b);
        Stage& s = ring[b % 8];
        std::vector<std::uint32_t>& ids = ids_[b & 1];
        std::vector<std::uint32_t>& lanes = lanes_[b & 1];
        TileRayBatch& t = s.batch;
        t.count = std::uint32_t(end - first);
        std::uint32_t found = 0;
        for (std::uint32_t lane = 0; lane < t.count; ++lane) {
            t.set(lane, rays[first + lane]);
            const std::uint32_t count = s.count[lane];
            if (count == 0) continue;
            if (ids.size() < found + count + 16) {
                ids.resize(2 * (found + count + 16));
                lanes.resize(ids.size());
            }
            found += kernels.batch_candidates(s.groups[lane], s.footprints[lane], s.ids[lane], s.first[lane], count,
                                              rays[first + lane].footprint, s.distinct[lane], lane, ids.data() + found,
                                              lanes.data() + found);
        }
        s.pairs = found;
        for (std::uint32_t p = 0; p < found; ++p) {
            const char* a = reinterpret_cast<const char*>(triangles + ids[p]);
            _mm_prefetch(a, _MM_HINT_T0);
            _mm_prefetch(a + sizeof(Triangle) - 1, _MM_HINT_T0);
        }
    };
    // Stage 6: the test.
    auto test = [&](std::size_t b) {
        const Stage& s = ring[b % 8];
        const std::uint32_t bits =
            kernels.batch_test(s.batch, triangles, ids_[b & 1].data(), lanes_[b & 1].data(), s.pairs, 0);
        for (std::uint32_t m = bits; m; m &= m - 1) {
            const std::uint32_t slot = s.batch.slot[__builtin_ctz(m)];
            occluded[slot / 16] |= 1u << (slot % 16);
        }
    };
    // Batch b is tested while b + 1 is scanned, b + 2 has its groups' entries requested, b + 3 its
    // leaves' entries (or groups), b + 5 its blocks' heads, b + 6 its tiles' headers, b + 7 its tile
    // entries and b + 7 + R its records (distances measured on the bunny's and the room's AO rays).
    // Under a memory budget the pipeline is drained every kQuiescentBatches batches, where the
    // thread holds no tile and says so (tile_cache.hpp): evicted blocks are then freed within a PSF.
    constexpr std::size_t R = 3, H = 2, L = 4, G = 5, C = 6, T = C + 1;
    const std::size_t segment = f.tile_cache->budgeted() ? kQuiescentBatches : batches;
    for (std::size_t b0 = 0; b0 < batches; b0 += segment) {
        const std::size_t b1 = std::min(batches, b0 + segment);
        for (std::size_t b = b0; b < b1 && b < b0 + R; ++b) request_rays(b);
        for (std::size_t b = b0; b < b1 + T; ++b) {
            if (b + R < b1) request_rays(b + R);
            if (b < b1) request_entries(b);
            if (b >= b0 + 1 && b - 1 < b1) request_headers(b - 1);
            if (b >= b0 + H && b - H < b1) request_heads(b - H);
            if (b >= b0 + L && b - L < b1) request_entries_of_leaves(b - L);
            if (b >= b0 + G && b - G < b1) request_groups(b - G);
            if (b >= b0 + C && b - C < b1) candidates(b - C);
            if (b >= b0 + T) test(b - T);
        }
        if (b1 < batches) f.quiescent();
    }
}

}  // namespace beamtrace::vlf
