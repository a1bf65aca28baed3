#include "mlrta/tile_tracer.hpp"

#include <algorithm>

#include "common/ray_validity.hpp"
#include "kdtree/packet/packet_traversal.hpp"
#include "mlrta/entry_point_search.hpp"
#include "mlrta/entry_point_trace.hpp"
#include "mlrta/shadow_reversal.hpp"

namespace beamtrace::mlrta {

template <bool kOcclusion, bool kCount>
TileTracer<kOcclusion, kCount>::TileTracer(const Mlrta::Impl& m, const PacketGrid& grid, PacketHits16* hits,
                                           std::uint32_t* occluded, QueryCounters* counters,
                                           const TileObserver* observer, bool reverse)
    : m_(m),
      grid_(grid),
      hits_(hits),
      occluded_(occluded),
      counters_(counters),
      observer_(observer),
      reverse_(kOcclusion && reverse) {
    tile_side_ = std::max(1, m.settings.initial_tile / 4);
    // The smallest tile: sides divided by the parts per side until no larger than the minimum;
    // cells only when every division is exact (then every tile of a whole initial tile is made of
    // whole cells).
    const int min_side = std::max(1, m.settings.min_tile / 4);
    const int parts = m.settings.split_factor == 4 ? 2 : 4;
    for (int side = tile_side_;; side /= parts) {
        if (side <= min_side) {
            cell_ = side;
            break;
        }
        if (side % parts != 0) break;  // uneven parts: cells of one packet
    }
    cells_ = (tile_side_ + cell_ - 1) / cell_;
    beams_.resize(std::size_t(cells_) * std::size_t(cells_));
    if (reverse_) {
        reversed_.resize(std::size_t(tile_side_) * std::size_t(tile_side_));
        tolerance_ = reversal_tolerance(m.kd().scene.bounds());
    }
    Beam scale;
    scale.set_scene_scale(m.kd().bounds);
    pad_ = scale.pad;
}

template <bool kOcclusion, bool kCount>
Beam TileTracer<kOcclusion, kCount>::tile_beam(int x0, int y0, int x1, int y1) const {
    Beam beam;
    beam.pad = pad_;
    const int end_x = std::min(tile_x0_ + tile_side_, grid_.columns), end_y = std::min(tile_y0_ + tile_side_, grid_.rows);
    auto aligned = [&](int a, int origin, int end) { return (a - origin) % cell_ == 0 || a == end; };
    if (aligned(x0, tile_x0_, end_x) && aligned(x1, tile_x0_, end_x) && aligned(y0, tile_y0_, end_y) &&
        aligned(y1, tile_y0_, end_y)) {
        for (int cy = (y0 - tile_y0_) / cell_; cy * cell_ + tile_y0_ < y1; ++cy)
            for (int cx = (x0 - tile_x0_) / cell_; cx * cell_ + tile_x0_ < x1; ++cx)
                beam.merge(beams_[std::size_t(cy) * std::size_t(cells_) + std::size_t(cx)]);
        return beam;
    }
    beam.add(packets_of(x0, y0, x1, y1), m_.kernels().setup.set_ranges);
    return beam;
}

template <bool kOcclusion, bool kCount>
std::span<const Packet16* const> TileTracer<kOcclusion, kCount>::packets_of(int x0, int y0, int x1, int y1) const {
    gathered_.clear();
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) gathered_.push_back(&packet(x, y));
    return gathered_;
}

template <bool kOcclusion, bool kCount>
const Packet16& TileTracer<kOcclusion, kCount>::packet(int x, int y) const {
    if (reverse_) return reversed_[std::size_t(y - tile_y0_) * std::size_t(tile_side_) + std::size_t(x - tile_x0_)];
    return grid_.packets[std::size_t(y) * std::size_t(grid_.columns) + std::size_t(x)];
}

template <bool kOcclusion, bool kCount>
void TileTracer<kOcclusion, kCount>::trace_initial_tile(int x0, int y0) {
    tile_x0_ = x0;
    tile_y0_ = y0;
    const int x1 = std::min(x0 + tile_side_, grid_.columns), y1 = std::min(y0 + tile_side_, grid_.rows);
    if (reverse_)
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x)
                reverse_for_occlusion(grid_.packets[std::size_t(y) * std::size_t(grid_.columns) + std::size_t(x)],
                                      tolerance_, reversed_[std::size_t(y - y0) * std::size_t(tile_side_) + std::size_t(x - x0)]);
    for (int cy = 0; cy < cells_; ++cy)
        for (int cx = 0; cx < cells_; ++cx) {
            Beam& b = beams_[std::size_t(cy) * std::size_t(cells_) + std::size_t(cx)];
            b = Beam{};
            b.pad = pad_;
            b.add(packets_of(x0 + cx * cell_, y0 + cy * cell_, std::min(x0 + (cx + 1) * cell_, x1),
                             std::min(y0 + (cy + 1) * cell_, y1)),
                  m_.kernels().setup.set_ranges);
        }
    trace_tile(x0, y0, x1, y1, root_entry(m_), nullptr, false);
}

template <bool kOcclusion, bool kCount>
void TileTracer<kOcclusion, kCount>::trace_tile(int x0, int y0, int x1, int y1, const EntryPoint& ep,
                                                const SearchTrail* trail, bool parent_stuck) {
    const Beam beam = tile_beam(x0, y0, x1, y1);
    if (beam.empty) {
        trace_packets(x0, y0, x1, y1, ep, false);  // no active ray: only clears the results
        return;
    }
    const int min_side = std::max(1, m_.settings.min_tile / 4);
    const bool small = (x1 - x0) <= min_side && (y1 - y0) <= min_side;
    const int parts = m_.settings.split_factor == 4 ? 2 : 4;  // per side
    EntryPoint found = ep;
    SearchTrail found_trail;  // stays invalid for diverging tiles: their parts search without one
    bool stuck = false;       // the search found the parent's entry point again
    if (!beam.coherent) {
        // Diverging rays: no entry-point search. At the minimum size the packets go to XP search
        // (in coherent sub-groups); larger tiles are split first, as their parts may be coherent.
        if (small) {
            trace_packets(x0, y0, x1, y1, ep, true);
            return;
        }
        if constexpr (kCount) ++counters_->mlrta.divergent_tiles;
    } else {
        std::uint64_t steps = 0;
        const bool resume = m_.settings.experimental.ep_resume;
        found = entry_point_search(m_, beam, ep, steps, resume ? trail : nullptr, resume ? &found_trail : nullptr);
        if constexpr (kCount) counters_->mlrta.ep_steps += steps;
        // Stop splitting at a leaf (the paper's rule), at the minimum size, or when the search made
        // no progress: a tile whose entry point is its parent's rarely has parts that do better,
        // and their searches would cost more than they save. With retry_stuck such a tile is split
        // once more (its parts often do find deeper entry points), unless it already is the part of
        // a stuck tile or its parts would be single packets.
        stuck = found.node == ep.node;
        const bool single_parts = (x1 - x0) <= parts && (y1 - y0) <= parts;
        const bool stop = stuck && m_.settings.experimental.stop_when_stuck &&
                          (!m_.settings.experimental.retry_stuck || parent_stuck || single_parts);
        if constexpr (kOcclusion) {
            if (found.blocked()) {  // one triangle occludes every ray of the tile
                occlude_all(x0, y0, x1, y1);
                return;
            }
        }
        if (found.misses || small || stop || m_.kd().nodes[found.node].is_leaf()) {
            trace_packets(x0, y0, x1, y1, found, false, &found_trail);
            return;
        }
    }
    const int w = x1 - x0, h = y1 - y0;
    for (int j = 0; j < parts; ++j)
        for (int i = 0; i < parts; ++i) {
            const int sx0 = x0 + w * i / parts, sx1 = x0 + w * (i + 1) / parts;
            const int sy0 = y0 + h * j / parts, sy1 = y0 + h * (j + 1) / parts;
            if (sx1 > sx0 && sy1 > sy0) trace_tile(sx0, sy0, sx1, sy1, found, &found_trail, stuck);
        }
}

template <bool kOcclusion, bool kCount>
void TileTracer<kOcclusion, kCount>::occlude_all(int x0, int y0, int x1, int y1) {
    if constexpr (kCount) {
        ++counters_->mlrta.tiles;
        ++counters_->mlrta.blocked_tiles;
    }
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const std::size_t p = std::size_t(y) * std::size_t(grid_.columns) + std::size_t(x);
            // The lanes the tile's beam was made of (Beam::add): every one of them is blocked.
            const Packet16& traced = packet(x, y);
            occluded_[p] = traced.active & 0xFFFFu & segment_lanes(traced);
            if constexpr (kCount) ++counters_->packets;
        }
}

template <bool kOcclusion, bool kCount>
void TileTracer<kOcclusion, kCount>::trace_packets(int x0, int y0, int x1, int y1, const EntryPoint& ep, bool divergent,
                                                   const SearchTrail* trail) {
    if constexpr (kCount) {
        ++counters_->mlrta.tiles;
        if (divergent) ++counters_->mlrta.divergent_tiles;
    }
    if (observer_ && *observer_) {
        const std::size_t subtree = m_.subtree_nodes[ep.node];
        (*observer_)(TileInfo{x0, y0, x1, y1, ep.node, ep.misses ? 0 : subtree, divergent});
    }
    // Blocks of side x side packets traced together (one packet at a time for diverging rays: their
    // blocks would not go together).
    const int side = divergent ? 1 : m_.settings.experimental.xp_packets;
    const Packet16* block[kdtree::kMaxTogether];
    PacketHits16* block_hits[kdtree::kMaxTogether];
    std::uint32_t* block_occluded[kdtree::kMaxTogether];
    for (int by = y0; by < y1; by += side)
        for (int bx = x0; bx < x1; bx += side) {
            int n = 0;
            for (int y = by; y < std::min(by + side, y1); ++y)
                for (int x = bx; x < std::min(bx + side, x1); ++x) {
                    const std::size_t p = std::size_t(y) * std::size_t(grid_.columns) + std::size_t(x);
                    block[n] = &packet(x, y);
                    block_hits[n] = kOcclusion ? nullptr : hits_ + p;
                    block_occluded[n] = kOcclusion ? occluded_ + p : nullptr;
                    ++n;
                }
            trace_packets_together<kOcclusion, kCount>(m_, block, n, ep, block_hits, block_occluded, counters_, trail);
        }
}

template class TileTracer<false, false>;
template class TileTracer<false, true>;
template class TileTracer<true, false>;
template class TileTracer<true, true>;

}  // namespace beamtrace::mlrta
