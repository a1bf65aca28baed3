#pragma once
// The rays of a binned occlusion stream (ray_stream.cpp) whose segments stay in the tile where they
// start (section 7: AO rays along PSF directions; in mode fast, every ray), traced in batches of 16
// (tile_ray_batch.hpp) instead of one walk each. The stream's first pass hands each looked-up ray
// to take(); the ones it keeps go, as 64-byte TileRays, into bins of one PSF and one square block of
// its tiles (chunks of a pool the field lends, kept from one call to the next, so that a timed pass
// does not pay for fresh pages, and freed with the field; VlfStats::stream_bytes counts it). The
// blocks are sized so that a bin holds about kRaysPerBlock rays: the tiles a bin's rays read stay in
// the caches while its rays are traced, in the order they came, with no sort and no second copy of
// the rays. trace() then takes the bins PSF by PSF and traces each PSF's rays as a pipeline:
//
//   batch b + 10: the rays' records requested from memory (R = 3 batches before their entries);
//   batch b + 7: the rays' tile entries requested;
//   batch b + 5: the entries read, the heads of the tiles' blocks (splits, leaf ends) requested;
//   batch b + 3: each ray's leaves found, their entries' footprints and ids requested (for a long
//                run, the groups' union footprints, tile_bsp.hpp);
//   batch b + 2: for a long run, the entries of the groups that meet the ray requested;
//   batch b + 1: the candidates (footprint scan) made, their triangles requested;
//   batch b:     the candidates tested.
//
// No lookup is made twice: a TileRay holds the leaf depths, the footprint and the watertight
// set-up its lookup gave.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "beamtrace/vlf.hpp"
#include "vlf/stream/packet_lookup.hpp"
#include "vlf/stream/tile_ray_batch.hpp"
#include "vlf/vlf_impl.hpp"

namespace beamtrace::vlf {

class TileRayBins {
public:
    // Empties the bins, for a stream of at most `rays` rays over `psfs` PSFs of `tiles_per_side`^2
    // tiles.
    void begin(std::size_t psfs, std::uint32_t tiles_per_side, std::size_t rays);
    // The lanes of a looked-up packet whose segment lies in their first tile (in mode fast, every
    // valid lane), binned; slot0 + i is lane i's place in the stream. Returns the lanes taken.
    std::uint32_t take(const VisibilityField::Impl& f, const Packet16& p, const PacketLookup& l, std::uint32_t slot0,
                       VlfMode mode);
    // Traces the kept rays; sets bit slot % 16 of occluded[slot / 16] for each occluded one.
    void trace(const VisibilityField::Impl& f, std::span<std::uint32_t> occluded);
    // Bytes held (the pool and the bins' lists).
    std::size_t bytes() const;
    // The side of a bin's block of tiles (for tests).
    std::uint32_t block_side() const { return 1u << shift_; }

    // Rays a bin aims at (begin sizes the blocks of tiles from the stream's rays per PSF).
    static constexpr std::size_t kRaysPerBlock = 1024;

private:
    // Up to 16 consecutive rays of one chunk.
    struct Batch {
        const TileRay* rays;
        std::uint32_t count;
    };
    static constexpr std::uint32_t kChunk = 64;
    static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
    static constexpr std::size_t kQuiescentBatches = 256;  // under a memory budget (tile_ray_stream.cpp)
    void trace_psf(const VisibilityField::Impl& f, const ParallelSubfield& psf, std::span<const Batch> batches,
                   std::span<std::uint32_t> occluded);

    std::unique_ptr<TileRay[]> pool_;  // chunks of kChunk rays
    std::size_t pool_size_ = 0;
    std::uint32_t chunks_ = 0;
    std::uint32_t shift_ = 0;           // a bin's block of tiles: 2^shift_ columns and rows
    std::uint32_t blocks_side_ = 1;     // blocks per side of the grid
    std::vector<std::uint32_t> link_;   // chunk -> the bin's previous chunk (kNone: first)
    std::vector<std::uint32_t> last_;   // bin (PSF * blocks_side_^2 + block) -> its newest chunk (kNone: none)
    std::vector<std::uint32_t> fill_;   // bin -> rays in its newest chunk
    std::vector<std::uint32_t> count_;  // PSF -> rays
    std::vector<Batch> batches_;        // of one PSF
    std::vector<std::uint32_t> ids_[2], lanes_[2];  // candidate pairs of two batches
    std::vector<std::uint32_t> passing_;            // groups of a long run that meet a ray
};

// A TileRayBins of the field's for the duration of one stream (taken from the field's spares, or
// made; given back at the end).
class TileRayLease {
public:
    explicit TileRayLease(const VisibilityField::Impl& f);
    ~TileRayLease();
    TileRayLease(const TileRayLease&) = delete;
    TileRayLease& operator=(const TileRayLease&) = delete;
    TileRayBins& bins() { return *bins_; }

private:
    const VisibilityField::Impl& field_;
    std::unique_ptr<TileRayBins> bins_;
};

}  // namespace beamtrace::vlf
