#pragma once
// TileBsp: the 1D BSP along one tile's beam (section 4). Split planes are orthogonal to the beam
// (constant canonical z), chosen as medians; a triangle goes to every leaf its (clipped, padded)
// depth range overlaps. The leaves are stored flat, in depth order, in one block of 32-bit words:
//
//     [ split_0 .. split_{m-2} ]  [ end_0 .. end_{m-1} ]  [ groups ]  [ footprints ... ]  [ ids ... ]
//                                                                                         3 bytes each
//                                                                                         (packed_ids.hpp)
//       float bits, ascending      leaf j holds entries end_{j-1} .. end_j - 1 (end_{-1} = 0);
//                                  footprints[k] (tile_footprint.hpp) belongs to ids[k], and the
//                                  footprints of a run of leaves are one run of memory for SIMD.
//                                  Footprints come first: every query reads them, right after the
//                                  splits and ends, while it reads only the ids of passing entries.
//
// Groups (not in the paper), in tiles of at least kGroupedTile entries only: word g is the union of
// the footprints of entries 16 g .. 16 g + 15 (bytewise minimum of the packed words), so a ray
// whose footprint misses it skips those 16 entries unread. Within a leaf of such a tile the entries
// are ordered along a Morton curve of their footprints' centres (ties by id; elsewhere by id), which
// keeps a group's union small: in a dense tile (thousands of small
// triangles, the room's desks) a ray meeting a small part of the tile reads few groups' entries.
//
// Leaf j covers depths [split_{j-1}, split_j] (the first and last are open-ended), so the first
// and last leaf a ray segment needs follow from the depths of its two ends (section 4, Figure 3).
#include <bit>
#include <cstdint>

#include <immintrin.h>
#include <span>
#include <vector>

#include "vlf/build/packed_ids.hpp"

namespace beamtrace::vlf {

// One triangle of a tile: its id, the depth range of its part inside the tile's prism (padded) and
// that part's footprint.
struct DepthItem {
    std::uint32_t id;
    float lo, hi;
    std::uint32_t footprint;
};

// Read access to a block of `leaves` leaves.
struct TileBspView {
    const std::uint32_t* block = nullptr;
    std::uint32_t leaves = 0;

    float split(std::uint32_t j) const { return std::bit_cast<float>(block[j]); }  // j < leaves - 1
    const std::uint32_t* ends() const { return block + (leaves - 1); }
    std::uint32_t begin(std::uint32_t j) const { return j == 0 ? 0 : ends()[j - 1]; }
    std::uint32_t end(std::uint32_t j) const { return ends()[j]; }
    std::uint32_t entries() const { return end(leaves - 1); }
    static constexpr std::uint32_t kGroup = 16;         // entries per group
    static constexpr std::uint32_t kGroupedTile = 256;  // tiles of at least this many entries have groups
    std::uint32_t groups_count() const {
        const std::uint32_t e = entries();
        return e >= kGroupedTile ? (e + kGroup - 1) / kGroup : 0;
    }
    // nullptr: the tile has no groups.
    const std::uint32_t* groups() const { return groups_count() ? block + (leaves - 1) + leaves : nullptr; }
    const std::uint32_t* footprints() const { return block + (leaves - 1) + leaves + groups_count(); }
    PackedIds ids() const { return PackedIds{reinterpret_cast<const std::uint8_t*>(footprints() + entries())}; }
    // The leaf whose depth range holds z (the lower one when z is a split): the number of splits
    // below z. Up to kCountedSplits splits are compared with z four at a time and the ones below
    // counted: independent loads and compares, where a binary search waits for each load before the
    // next (PSF-aligned AO rays of the bunny: 2% faster). More splits (dense tiles) go by a
    // binary search of fixed steps (the splits ascend strictly), whose selects need no branch on the
    // data. Both give the same count. z is compared as a float; where that rounding moves it across
    // a split, the triangles near z (padded far more than a float's rounding) are in both leaves.
    static constexpr std::uint32_t kCountedSplits = 32;
    std::uint32_t leaf(double z) const {
        const float zf = float(z);
        const std::uint32_t splits = leaves - 1;
        if (splits <= kCountedSplits) {
            // A load may run past the last split into the leaf ends (masked off below): a block
            // holds at least splits + 3 words after its first split (the ends, one footprint, one id's word).
            const __m128 q = _mm_set1_ps(zf);
            std::uint32_t below = 0;
            for (std::uint32_t k = 0; k < splits; k += 4) {
                auto bits = std::uint32_t(
                    _mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(reinterpret_cast<const float*>(block + k)), q)));
                if (splits - k < 4) bits &= (1u << (splits - k)) - 1u;
                below += std::uint32_t(std::popcount(bits));
            }
            return below;
        }
        std::uint32_t j = 0;
        for (std::uint32_t step = std::bit_floor(splits); step; step >>= 1) {
            const std::uint32_t next = j + step;
            j = next <= splits && split(next - 1) < zf ? next : j;
        }
        return j;
    }
    std::uint32_t words() const {
        return (leaves - 1) + leaves + groups_count() + entries() + std::uint32_t(PackedIds::words_of(entries()));
    }
};

class TileBspBuilder {
public:
    // Leaves holding at most this many triangles are not split further.
    static constexpr std::size_t kLeafTriangles = 16;
    // Beyond the chosen depth, leaves still holding more than kDenseLeaf triangles keep splitting,
    // down to kMaxDepth (a deviation from the paper's uniform depth, for dense tiles).
    static constexpr std::size_t kDenseLeaf = 64;
    static constexpr int kMaxDepth = 16;

    explicit TileBspBuilder(int depth) : depth_(depth), levels_(std::size_t(kMaxDepth) + 1) {}

    // Builds the tile-BSP of items (sorted by id, non-empty) into `block` (replaced); returns the
    // number of leaves. The same items always give the same block.
    std::uint32_t build(std::span<const DepthItem> items, std::vector<std::uint32_t>& block);

private:
    void node(int level, float lo, float hi);
    static std::uint32_t footprint_order(std::uint32_t footprint);
    struct Ordered {
        std::uint32_t key, id, footprint;
    };

    int depth_;
    std::vector<std::vector<DepthItem>> levels_;  // items of the node being built at each level
    std::vector<float> centres_;
    std::vector<float> splits_;
    std::vector<std::uint32_t> ends_, ids_, footprints_;
    std::vector<Ordered> order_;
};

}  // namespace beamtrace::vlf
