#pragma once
// The lazily made cells of one ray classification: six face roots over an origin box (the scene's
// box for the 5D tree; a light buffer's tiny box around a shared point), children made the first
// time a ray reaches them, published with a compare-and-swap so readers never lock. A child halves
// the direction rectangle (4 children) and, in the 5D tree, the origin box too (32 children: one of
// the thesis's levels). A cell with few candidates, or at the depth limit, keeps its list for rays.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "beamtrace/query.hpp"
#include "raycls/candidate_list.hpp"
#include "raycls/direction_grid.hpp"
#include "raycls/ray_space.hpp"

namespace beamtrace::raycls {

// What every cell tree of a classification shares: the kd-tree, the rules, the margins and the
// accounting.
struct CellContext {
    const KdTree::Impl* tree = nullptr;
    int min_candidates = 6;
    std::size_t memory_budget = 0;  // 0: unbounded
    double origin_margin = 0.0, direction_margin = 0.0;
    std::atomic<std::size_t> bytes{0}, peak_bytes{0};
    std::atomic<std::uint64_t> cells_created{0}, cells_freed{0}, entries{0}, build_ns{0}, epoch{1};
    // Entries made so far, and how many may be (entries_per_ray x rays of the calls so far; 0: no cap).
    std::atomic<std::uint64_t> entries_made{0}, entry_allowance{0};
    bool capped = false;
    // Set within a call whose rays rarely reach a made cell (ray_classification.cpp): no cell is
    // made until the next call.
    std::atomic<bool> growth_stopped{false};
    std::atomic<std::uint64_t> growth_stops{0};
    // Set within a call when a made cell did not fit in the budget (it was dropped, and no cell is
    // made until the next call, which frees old cells first).
    std::atomic<bool> budget_full{false};
    std::atomic<int> max_depth_reached{0};

    void add_bytes(std::size_t b);
    // Adds b unless that takes the bytes held past the budget (then false, nothing added), so that the
    // cells never hold more than the budget, whatever the size of the last cell made.
    bool reserve_bytes(std::size_t b);
    void remove_bytes(std::size_t b) { bytes.fetch_sub(b, std::memory_order_relaxed); }
    // New cells may be made (neither the memory budget nor the work cap is exhausted).
    bool may_grow() const {
        if (growth_stopped.load(std::memory_order_relaxed) || budget_full.load(std::memory_order_relaxed)) return false;
        if (capped && entries_made.load(std::memory_order_relaxed) >= entry_allowance.load(std::memory_order_relaxed))
            return false;
        return memory_budget == 0 || bytes.load(std::memory_order_relaxed) < memory_budget;
    }
};

struct Cell {
    CellBounds bounds;
    CandidateList list;                    // 5D cells
    std::unique_ptr<DirectionGrid> grid;   // a light buffer's tiles
    bool whole_scene = false;  // no list (a root, or above the first level with lists): rays pass through
    bool final = false;        // rays use the list; no children
    int depth = 0;
    std::unique_ptr<std::atomic<Cell*>[]> children;  // 4 or 32 slots unless final
    std::unique_ptr<std::atomic<std::uint32_t>[]> requests;  // rays that reached each missing child
    std::atomic<std::uint64_t> last_used{0};         // the context's epoch of the last ray here

    std::size_t memory_bytes(int slots) const {
        return sizeof(Cell) + list.memory_bytes() + (grid ? grid->memory_bytes() : 0) +
               (final ? 0 : std::size_t(slots) * (sizeof(void*) + (requests ? sizeof(std::uint32_t) : 0)));
    }
};

class CellTree {
public:
    // split_origins: the 5D tree (32 children); false: a light buffer (4). Cells above first_list_depth
    // hold no list (rays pass through them); those at it get theirs from the kd-tree. A light buffer's
    // cells at first_list_depth are its tiles: final, each with a grid of up to 2^(max_depth -
    // first_list_depth) cells a side (about min_candidates candidates per cell). A cell is made
    // when the rays_per_new_cell-th ray reaches its place (find() returns nullptr for the ones before).
    CellTree(CellContext& context, const Box& origins, bool split_origins, int max_depth, int first_list_depth,
             int rays_per_new_cell);
    ~CellTree();
    CellTree(const CellTree&) = delete;
    CellTree& operator=(const CellTree&) = delete;

    // The final cell of the point p (inside origins(), or anywhere for a light buffer) and direction;
    // nullptr when a cell on the way is not made yet: too few rays have reached it, or the memory
    // budget is exhausted.
    template <bool kCount>
    const Cell* find(const float p[3], const DirectionCode& d, QueryCounters* counters) const;

    const Box& origins() const { return origins_; }
    bool split_origins() const { return split_origins_; }
    int slots() const { return split_origins_ ? 32 : 4; }

    // An entry per non-root cell (for prune(), below); frees a cell and its subtree. Only while no
    // thread queries.
    void collect_prunable(std::vector<struct PruneEntry>& out) const;
    void free_subtree(std::atomic<Cell*>& slot) const;

private:
    Cell* child(Cell& parent, int index) const;
    Cell* make_child(const Cell& parent, int index) const;
    void add_slots(Cell& c) const;
    void delete_cell(Cell* c) const;

    CellContext& context_;
    Box origins_;
    bool split_origins_;
    int max_depth_;
    int first_list_depth_;
    std::uint32_t rays_per_new_cell_;
    std::unique_ptr<Cell> roots_[6];
};

struct PruneEntry {
    std::uint64_t last_used;  // of the subtree
    int depth;
    std::atomic<Cell*>* slot;
    const CellTree* tree;
};

// The least recently used subtrees of the trees freed until the context holds at most target bytes.
void prune(CellContext& context, const std::vector<const CellTree*>& trees, std::size_t target);

template <bool kCount>
const Cell* CellTree::find(const float p[3], const DirectionCode& d, QueryCounters* counters) const {
    Cell* c = roots_[d.face].get();
    while (!c->final) {
        c = child(*c, child_index(c->bounds, p, d.u, d.v, split_origins_));
        if (!c) return nullptr;
        if constexpr (kCount) ++counters->raycls.descent_steps;
    }
    const std::uint64_t epoch = context_.epoch.load(std::memory_order_relaxed);
    if (c->last_used.load(std::memory_order_relaxed) != epoch) c->last_used.store(epoch, std::memory_order_relaxed);
    return c;
}

}  // namespace beamtrace::raycls
