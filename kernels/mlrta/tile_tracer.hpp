#pragma once
// The tile tracer: adaptive tile splitting (MLRTA section 4.2) and the tracing of the tiles' packets.
// A tile of packets becomes a beam; its entry point is searched from its parent's; it is split into
// SF sub-tiles until its entry point is a leaf or it is no larger than the minimum tile size, then
// its packets are traced by interval traversal from that entry point, in blocks of xp_packets x
// xp_packets packets traced together (kdtree::trace_packets_together). Tiles whose rays diverge in
// sign go straight to XP search from the parent's entry point (for their coherent sub-groups) once
// they reach the minimum size; larger diverging tiles are split first (their parts may be coherent:
// shadow beams from a light often are). Occlusion tiles can be traced from their light: each
// initial tile's packets are reversed (shadow_reversal.hpp) into a buffer of the tracer's, one
// initial tile at a time.
#include <span>
#include <vector>

#include "beamtrace/mlrta.hpp"
#include "beamtrace/query.hpp"
#include "mlrta/beam.hpp"
#include "mlrta/entry_point.hpp"
#include "mlrta/mlrta_impl.hpp"

namespace beamtrace::mlrta {

template <bool kOcclusion, bool kCount>
class TileTracer {
public:
    // Beams of cells (the smallest tiles the splitting can make: a packet with the paper's minimum tile)
    // are computed once per initial tile and merged for sub-tiles. With `reverse`
    // (occlusion only), packets are traced reversed towards their light when the policy allows.
    TileTracer(const Mlrta::Impl& m, const PacketGrid& grid, PacketHits16* hits, std::uint32_t* occluded,
               QueryCounters* counters, const TileObserver* observer, bool reverse = false);

    // Traces the initial tile with its top-left packet (x0, y0), ITS / 4 packets on a side.
    void trace_initial_tile(int x0, int y0);

private:
    // `trail`: of the search that found `ep` for a beam holding this tile's (null if none);
    // `parent_stuck`: that search found its own parent's entry point again.
    void trace_tile(int x0, int y0, int x1, int y1, const EntryPoint& ep, const SearchTrail* trail, bool parent_stuck);
    // `trail`: of the search that found `ep` for this tile's beam (null if none).
    void trace_packets(int x0, int y0, int x1, int y1, const EntryPoint& ep, bool divergent,
                       const SearchTrail* trail = nullptr);
    // Occlusion: a triangle blocks every ray of the tile (the entry-point search proved it).
    void occlude_all(int x0, int y0, int x1, int y1);
    // The beam of the tile's rays: merged from its cells' beams when the tile is made of whole
    // cells, from its packets otherwise.
    Beam tile_beam(int x0, int y0, int x1, int y1) const;
    // The packets of the rectangle [x0, x1) x [y0, y1), row by row, as traced (valid until the next call).
    std::span<const Packet16* const> packets_of(int x0, int y0, int x1, int y1) const;
    // The packet (x, y) as traced: the grid's, or its reversed copy.
    const Packet16& packet(int x, int y) const;

    const Mlrta::Impl& m_;
    PacketGrid grid_;
    PacketHits16* hits_;
    std::uint32_t* occluded_;
    QueryCounters* counters_;
    const TileObserver* observer_;
    bool reverse_ = false;
    double tolerance_ = 0.0;  // of the reversal policy
    int tile_x0_ = 0, tile_y0_ = 0, tile_side_ = 0;
    float pad_ = 0.0f;                // Beam::pad for the tree's scene (set_scene_scale, computed once)
    int cell_ = 1;                    // beams are kept per cell of cell_ x cell_ packets: no tile is smaller
    int cells_ = 0;                   // cells per side of an initial tile
    std::vector<Beam> beams_;         // of the cells of the current initial tile
    mutable std::vector<const Packet16*> gathered_;  // packets_of's answer
    std::vector<Packet16> reversed_;  // with reverse_: the current initial tile's packets as traced
};

}  // namespace beamtrace::mlrta
