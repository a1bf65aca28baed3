// TileBsp construction: median splits down to the chosen depth (fewer where they stop helping).
#include <algorithm>
#include <limits>

#include "vlf/build/tile_bsp.hpp"

namespace beamtrace::vlf {

namespace {

// Spreads the 8 bits of v to the even bits of a 16-bit word.
std::uint32_t spread(std::uint32_t v) {
    v = (v | (v << 4)) & 0x0F0Fu;
    v = (v | (v << 2)) & 0x3333u;
    v = (v | (v << 1)) & 0x5555u;
    return v;
}

}  // namespace

// The place of a footprint's centre on a Morton curve over the tile's lattice.
std::uint32_t TileBspBuilder::footprint_order(std::uint32_t f) {
    const std::uint32_t x = ((f & 0xFFu) + (255u - ((f >> 16) & 0xFFu))) / 2u;
    const std::uint32_t y = (((f >> 8) & 0xFFu) + (255u - ((f >> 24) & 0xFFu))) / 2u;
    return spread(x) | (spread(y) << 1);
}

std::uint32_t TileBspBuilder::build(std::span<const DepthItem> items, std::vector<std::uint32_t>& block) {
    splits_.clear();
    ends_.clear();
    ids_.clear();
    footprints_.clear();
    levels_[0].assign(items.begin(), items.end());
    node(0, -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity());
    // A tile with groups: each leaf's entries along a Morton curve of their footprints' centres.
    const bool grouped = ids_.size() >= TileBspView::kGroupedTile;
    for (std::size_t j = 0; grouped && j < ends_.size(); ++j) {
        const std::size_t a = j == 0 ? 0 : ends_[j - 1], b = ends_[j];
        order_.clear();
        for (std::size_t k = a; k < b; ++k)
            order_.push_back({footprint_order(footprints_[k]), ids_[k], footprints_[k]});
        std::sort(order_.begin(), order_.end(),
                  [](const Ordered& x, const Ordered& y) { return x.key != y.key ? x.key < y.key : x.id < y.id; });
        for (std::size_t k = a; k < b; ++k) {
            ids_[k] = order_[k - a].id;
            footprints_[k] = order_[k - a].footprint;
        }
    }
    const auto leaves = std::uint32_t(ends_.size());
    block.clear();
    block.reserve(splits_.size() + ends_.size() + ids_.size() / TileBspView::kGroup + 1 + ids_.size() +
                  PackedIds::words_of(ids_.size()));
    for (float s : splits_) block.push_back(std::bit_cast<std::uint32_t>(s));
    block.insert(block.end(), ends_.begin(), ends_.end());
    for (std::size_t g = 0; grouped && g < footprints_.size(); g += TileBspView::kGroup) {
        std::uint32_t u = 0xFFFFFFFFu;  // bytewise minimum: the union of the boxes
        for (std::size_t k = g; k < footprints_.size() && k < g + TileBspView::kGroup; ++k)
            for (int shift = 0; shift < 32; shift += 8) {
                const std::uint32_t mask = 0xFFu << shift;
                if ((footprints_[k] & mask) < (u & mask)) u = (u & ~mask) | (footprints_[k] & mask);
            }
        block.push_back(u);
    }
    block.insert(block.end(), footprints_.begin(), footprints_.end());
    const std::size_t at = block.size();
    block.resize(at + PackedIds::words_of(ids_.size()));
    PackedIds::pack(ids_.data(), ids_.size(), block.data() + at);
    return leaves;
}

// The node holding levels_[level], covering depths [lo, hi]. Its split is the median of the
// centres of its items' depth ranges cut to [lo, hi], so it always falls inside the node and the
// splits of the whole tree come out ascending when leaves are emitted left to right. A node
// becomes a leaf at the chosen depth (unless dense: see kDenseLeaf), when it holds few
// triangles, or, above the chosen depth, when more than half of its triangles straddle the split
// (they would be copied into both children: rays would save little and memory would grow).
// Below it, dense leaves keep splitting while each side gets at most 3/4 of the node: slabs of a
// finely tessellated object hold mostly straddling triangles, yet each slab is smaller.
void TileBspBuilder::node(int level, float lo, float hi) {
    const std::vector<DepthItem>& items = levels_[std::size_t(level)];
    auto leaf = [&] {
        for (const DepthItem& it : items) {
            ids_.push_back(it.id);
            footprints_.push_back(it.footprint);
        }
        ends_.push_back(std::uint32_t(ids_.size()));
    };
    const bool dense = depth_ > 0 && items.size() > kDenseLeaf && level < kMaxDepth;
    if ((level >= depth_ && !dense) || items.size() <= kLeafTriangles) return leaf();
    centres_.clear();
    for (const DepthItem& it : items) centres_.push_back(0.5f * (std::max(it.lo, lo) + std::min(it.hi, hi)));
    const auto mid = centres_.begin() + std::ptrdiff_t(centres_.size() / 2);
    std::nth_element(centres_.begin(), mid, centres_.end());
    const float split = *mid;
    if (!(split > lo && split < hi)) return leaf();
    std::size_t below = 0, above = 0;
    for (const DepthItem& it : items) {
        below += it.lo <= split;
        above += it.hi >= split;
    }
    if (level < depth_) {
        // A split that puts more than half of the node in both children copies more than it separates.
        if (2 * (below + above) > 3 * items.size()) return leaf();
    } else if (4 * std::max(below, above) > 3 * items.size()) {
        return leaf();  // beyond the chosen depth (dense leaves) a split must pay: each side <= 3/4
    }

    std::vector<DepthItem>& child = levels_[std::size_t(level) + 1];
    child.clear();
    for (const DepthItem& it : items)
        if (it.lo <= split) child.push_back(it);
    node(level + 1, lo, split);
    splits_.push_back(split);
    child.clear();
    for (const DepthItem& it : items)
        if (it.hi >= split) child.push_back(it);
    node(level + 1, split, hi);
}

}  // namespace beamtrace::vlf
