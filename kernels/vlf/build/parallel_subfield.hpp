#pragma once
// ParallelSubfield (PSF): the n x n parallel beams of one direction (section 3.1) with their
// tile-BSPs. Storage: one TileRef per tile and a pool of 32-bit words holding every non-empty
// tile's TileBsp block (see tile_bsp.hpp); a fresh build packs the blocks back to back. Dynamic
// updates (section 8) rebuild the blocks of the tiles a moved triangle touches, in place when the
// new block fits the old one's room, else at the end of the pool.
#include <algorithm>
#include <cstdint>

#include <immintrin.h>
#include <span>
#include <vector>

#include "beamtrace/scene.hpp"
#include "vlf/directions/canonical_frame.hpp"
#include "vlf/build/prism_clip.hpp"
#include "vlf/build/tile_bsp.hpp"

namespace beamtrace::vlf {

struct TileRef {
    std::uint32_t offset = 0;  // first word of the tile's block in the pool
    std::uint32_t leaves = 0;  // 0: the tile's beam meets no triangle
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
    ParallelSubfield(const CanonicalFrame& frame, const SubfieldInput& input);

    const CanonicalFrame& frame() const { return frame_; }
    TileRef tile(std::uint32_t index) const { return tiles_[index]; }
    TileBspView view(TileRef ref) const { return TileBspView{pool_.data() + ref.offset, ref.leaves}; }
    // Asks the cache for a tile's entry, or for words [first, first + count) of its block.
    void prefetch_tile(std::uint32_t index) const {
        _mm_prefetch(reinterpret_cast<const char*>(&tiles_[index]), _MM_HINT_T0);
    }
    void prefetch_block(TileRef ref, std::uint32_t first, std::uint32_t count) const {
        const char* a = reinterpret_cast<const char*>(pool_.data() + ref.offset + first);
        const char* b = reinterpret_cast<const char*>(pool_.data() + ref.offset + first + (count ? count : 1));
        for (const char* p = a; p < b; p += 64) _mm_prefetch(p, _MM_HINT_T0);
    }

    // Dynamic updates. remove: the triangles `ids` (already marked absent in input.present, still
    // with the corners they were inserted with) leave every tile they were in. insert: the
    // triangles `ids` (marked present, with their new corners) enter every tile they touch.
    void remove(std::span<const std::uint32_t> ids, const SubfieldInput& input);
    void insert(std::span<const std::uint32_t> ids, const SubfieldInput& input);

    std::size_t entries() const { return entries_; }  // triangle ids over all leaves
    std::size_t leaves() const { return leaves_; }
    std::size_t memory_bytes() const;
    double build_seconds() const { return build_seconds_; }

private:
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
    std::vector<TileRef> tiles_;
    std::vector<std::uint32_t> room_;  // words the block of each tile may grow to in place
    std::vector<std::uint32_t> pool_;
    std::size_t garbage_ = 0;  // pool words no tile uses any more (moved blocks)
    std::size_t entries_ = 0, leaves_ = 0;
    double build_seconds_ = 0.0;

    // Scratch of builds and updates.
    TileBspBuilder bsp_;
    std::vector<DepthItem> items_;
    std::vector<std::uint32_t> block_;
};

}  // namespace beamtrace::vlf
