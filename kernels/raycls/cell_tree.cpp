// Lazily made ray-space cells (cell_tree.hpp).
#include "raycls/cell_tree.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace beamtrace::raycls {

namespace {

// A parent list longer than this is not filtered: its child's candidates come from the kd-tree,
// whose culling of whole subtrees costs less than testing every one of the parent's triangles.
constexpr std::size_t kLargestFilteredList = 16384;

}  // namespace

namespace {

void raise_peak(std::atomic<std::size_t>& peak_bytes, std::size_t now) {
    std::size_t peak = peak_bytes.load(std::memory_order_relaxed);
    while (now > peak && !peak_bytes.compare_exchange_weak(peak, now, std::memory_order_relaxed)) {
    }
}

}  // namespace

void CellContext::add_bytes(std::size_t b) {
    raise_peak(peak_bytes, bytes.fetch_add(b, std::memory_order_relaxed) + b);
}

bool CellContext::reserve_bytes(std::size_t b) {
    if (memory_budget == 0) {
        add_bytes(b);
        return true;
    }
    std::size_t now = bytes.load(std::memory_order_relaxed);
    do {
        if (now + b > memory_budget) return false;
    } while (!bytes.compare_exchange_weak(now, now + b, std::memory_order_relaxed));
    raise_peak(peak_bytes, now + b);
    return true;
}

void CellTree::add_slots(Cell& c) const {
    const std::size_t n = std::size_t(slots());
    c.children = std::make_unique<std::atomic<Cell*>[]>(n);
    for (std::size_t i = 0; i < n; ++i) c.children[i].store(nullptr, std::memory_order_relaxed);
    if (rays_per_new_cell_ > 1) {
        c.requests = std::make_unique<std::atomic<std::uint32_t>[]>(n);
        for (std::size_t i = 0; i < n; ++i) c.requests[i].store(0, std::memory_order_relaxed);
    }
}

CellTree::CellTree(CellContext& context, const Box& origins, bool split_origins, int max_depth, int first_list_depth,
                   int rays_per_new_cell)
    : context_(context),
      origins_(origins),
      split_origins_(split_origins),
      max_depth_(max_depth),
      first_list_depth_(std::clamp(first_list_depth, 1, max_depth)),
      rays_per_new_cell_(std::uint32_t(std::max(1, rays_per_new_cell))) {
    for (int f = 0; f < 6; ++f) {
        auto root = std::make_unique<Cell>();
        for (int k = 0; k < 3; ++k) {
            root->bounds.lo[k] = origins.lower[k];
            root->bounds.hi[k] = origins.upper[k];
        }
        root->bounds.face = f;
        root->whole_scene = true;
        add_slots(*root);
        context_.add_bytes(root->memory_bytes(slots()));
        roots_[f] = std::move(root);
    }
}

CellTree::~CellTree() {
    for (auto& root : roots_) {
        for (int i = 0; i < slots(); ++i) free_subtree(root->children[std::size_t(i)]);
        context_.remove_bytes(root->memory_bytes(slots()));
    }
}

Cell* CellTree::make_child(const Cell& parent, int index) const {
    const auto start = std::chrono::steady_clock::now();
    const auto add_build_time = [&] {
        const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start);
        context_.build_ns.fetch_add(std::uint64_t(ns.count()), std::memory_order_relaxed);
    };
    auto c = std::make_unique<Cell>();
    c->bounds = child_bounds(parent.bounds, index, split_origins_);
    c->depth = parent.depth + 1;
    std::size_t entries = 0;
    if (c->depth < first_list_depth_) {
        c->whole_scene = true;
    } else if (!split_origins_) {
        // A light buffer's tile: its candidates with their direction rectangles, then its grid.
        const CellBeam beam = make_cell_beam(c->bounds, context_.origin_margin, context_.direction_margin);
        CandidateList tile = candidates_from_tree(*context_.tree, beam, c->bounds.face);
        add_direction_rects(tile, origins_, c->bounds.face, context_.direction_margin);
        const double per_cell = double(std::max(1, context_.min_candidates));
        const int levels = std::clamp(int(std::ceil(std::log2(std::max(1.0, double(tile.size()) / per_cell)) / 2.0)),
                                      0, max_depth_ - c->depth);
        c->grid = std::make_unique<DirectionGrid>(make_direction_grid(tile, c->bounds, levels, context_.tree->scene));
        c->final = true;
        entries = c->grid->items.size();
    } else {
        const CellBeam beam = make_cell_beam(c->bounds, context_.origin_margin, context_.direction_margin);
        if (parent.whole_scene || parent.list.size() > kLargestFilteredList)
            c->list = candidates_from_tree(*context_.tree, beam, c->bounds.face);
        else
            c->list = candidates_from_parent(parent.list, beam);
        c->final = c->list.size() <= std::size_t(context_.min_candidates) || c->depth >= max_depth_;
        entries = c->list.size();
    }
    if (!c->final) add_slots(*c);
    if (!context_.reserve_bytes(c->memory_bytes(slots()))) {
        // Over the budget (a light buffer's tile can be large): dropped; its rays go to the kd-tree.
        context_.budget_full.store(true, std::memory_order_relaxed);
        add_build_time();
        return nullptr;
    }
    context_.entries.fetch_add(entries, std::memory_order_relaxed);
    context_.entries_made.fetch_add(entries, std::memory_order_relaxed);
    context_.cells_created.fetch_add(1, std::memory_order_relaxed);
    int deepest = context_.max_depth_reached.load(std::memory_order_relaxed);
    while (c->depth > deepest &&
           !context_.max_depth_reached.compare_exchange_weak(deepest, c->depth, std::memory_order_relaxed)) {
    }
    add_build_time();
    return c.release();
}

Cell* CellTree::child(Cell& parent, int index) const {
    std::atomic<Cell*>& slot = parent.children[std::size_t(index)];
    Cell* c = slot.load(std::memory_order_acquire);
    if (c) return c;
    if (rays_per_new_cell_ > 1 &&
        parent.requests[std::size_t(index)].fetch_add(1, std::memory_order_relaxed) + 1 < rays_per_new_cell_)
        return nullptr;
    if (!context_.may_grow()) return nullptr;
    Cell* made = make_child(parent, index);
    if (!made) return nullptr;
    Cell* expected = nullptr;
    if (slot.compare_exchange_strong(expected, made, std::memory_order_acq_rel, std::memory_order_acquire))
        return made;
    // Another thread made the same cell first (the same candidates: a cell's set is a function of
    // its bounds); keep theirs.
    context_.cells_created.fetch_sub(1, std::memory_order_relaxed);
    delete_cell(made);
    return expected;
}

void CellTree::delete_cell(Cell* c) const {
    if (!c) return;
    if (!c->final)
        for (int i = 0; i < slots(); ++i) delete_cell(c->children[std::size_t(i)].exchange(nullptr));
    context_.remove_bytes(c->memory_bytes(slots()));
    context_.entries.fetch_sub(c->grid ? c->grid->items.size() : c->list.size(), std::memory_order_relaxed);
    delete c;
}

void CellTree::free_subtree(std::atomic<Cell*>& slot) const {
    Cell* c = slot.exchange(nullptr);
    if (!c) return;
    std::uint64_t count = 0;
    // Count the cells freed (the subtree's).
    std::vector<const Cell*> todo{c};
    while (!todo.empty()) {
        const Cell* x = todo.back();
        todo.pop_back();
        ++count;
        if (!x->final)
            for (int i = 0; i < slots(); ++i)
                if (const Cell* y = x->children[std::size_t(i)].load(std::memory_order_relaxed)) todo.push_back(y);
    }
    context_.cells_freed.fetch_add(count, std::memory_order_relaxed);
    delete_cell(c);
}

namespace {

// The latest use in c's subtree; appends an entry for every non-root cell.
std::uint64_t collect(const CellTree& tree, const Cell& c, std::atomic<Cell*>* slot,
                      std::vector<PruneEntry>& out) {
    std::uint64_t last = c.last_used.load(std::memory_order_relaxed);
    if (!c.final)
        for (int i = 0; i < tree.slots(); ++i) {
            std::atomic<Cell*>& s = c.children[std::size_t(i)];
            if (const Cell* y = s.load(std::memory_order_relaxed)) last = std::max(last, collect(tree, *y, &s, out));
        }
    if (slot) out.push_back(PruneEntry{last, c.depth, slot, &tree});
    return last;
}

}  // namespace

void CellTree::collect_prunable(std::vector<PruneEntry>& out) const {
    for (const auto& root : roots_) collect(*this, *root, nullptr, out);
}

void prune(CellContext& context, const std::vector<const CellTree*>& trees, std::size_t target) {
    if (context.bytes.load() <= target) return;
    std::vector<PruneEntry> entries;
    for (const CellTree* t : trees) t->collect_prunable(entries);
    // Oldest first; a subtree is never older than its cells, and deeper cells go first among equals,
    // so a cell is freed before (or with) its parent, never after.
    std::sort(entries.begin(), entries.end(), [](const PruneEntry& a, const PruneEntry& b) {
        return a.last_used < b.last_used || (a.last_used == b.last_used && a.depth > b.depth);
    });
    for (const PruneEntry& e : entries) {
        if (context.bytes.load() <= target) break;
        e.tree->free_subtree(*e.slot);
    }
}

}  // namespace beamtrace::raycls
