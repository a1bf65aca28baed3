// The moving triangles over one time bin (moving_bin.hpp).
#include "raycls/moving_bin.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "common/radix_sort.hpp"
#include "common/ray_validity.hpp"
#include "common/watertight_ray.hpp"
#include "kdtree/ray_traversal.hpp"
#include "raycls/candidate_tests.hpp"
#include "raycls/cell_beam.hpp"

namespace beamtrace::raycls {

namespace {

// Zero area in double precision, as Scene decides it: a snapshot keeps such a triangle out of every
// query, so a moving triangle that collapses at the ray's time must not be hit either.
bool zero_area(const Triangle& t) {
    const double ax = double(t.v1.x) - t.v0.x, ay = double(t.v1.y) - t.v0.y, az = double(t.v1.z) - t.v0.z;
    const double bx = double(t.v2.x) - t.v0.x, by = double(t.v2.y) - t.v0.y, bz = double(t.v2.z) - t.v0.z;
    return ay * bz - az * by == 0.0 && az * bx - ax * bz == 0.0 && ax * by - ay * bx == 0.0;
}

float key_of(const Box& b, int face) {
    const int k = face_axis(face);
    return face_sign(face) > 0 ? b.lower[k] : -b.upper[k];
}

void sort_by_key(std::vector<MovingCandidate>& items) {
    std::sort(items.begin(), items.end(), [](const MovingCandidate& a, const MovingCandidate& b) {
        return a.key < b.key || (a.key == b.key && a.index < b.index);
    });
}

// Up to eight candidates from `first`, placed at `time` (read from `placed` when given), against the
// ray; batch[j] is candidate j as tested.
int test_at_time(const MovingContext& c, const WatertightRay& w, std::span<const MovingCandidate> items,
                 std::size_t first, float time, const Triangle* placed, Triangle (&tris)[8],
                 const Triangle* (&batch)[8], LaneHits& lanes) {
    const int count = int(std::min<std::size_t>(8, items.size() - first));
    for (int j = 0; j < count; ++j) {
        const std::uint32_t index = items[first + std::size_t(j)].index;
        if (placed) {
            batch[j] = placed + index;
        } else {
            tris[j] = c.scene->triangle_at((*c.moving)[index], time);
            batch[j] = &tris[j];
        }
    }
    if (count <= 4)
        c.kernels->ray_x4(w, batch, count, lanes);
    else
        c.kernels->ray_x8(w, batch, count, lanes);
    return count;
}

}  // namespace

void place_moving(const MovingContext& context, float t, std::vector<Triangle>& out) {
    out.resize(context.moving->size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = context.scene->triangle_at((*context.moving)[i], t);
}

void MovingContext::add(std::size_t b, std::size_t n) {
    const std::size_t now = bytes.fetch_add(b, std::memory_order_relaxed) + b;
    std::size_t peak = peak_bytes.load(std::memory_order_relaxed);
    while (now > peak && !peak_bytes.compare_exchange_weak(peak, now, std::memory_order_relaxed)) {
    }
    cells.fetch_add(1, std::memory_order_relaxed);
    entries.fetch_add(n, std::memory_order_relaxed);
}

void MovingContext::remove(std::size_t b, std::size_t n) {
    bytes.fetch_sub(b, std::memory_order_relaxed);
    cells.fetch_sub(1, std::memory_order_relaxed);
    entries.fetch_sub(n, std::memory_order_relaxed);
}

std::size_t MovingBin::bytes_of(const MovingCell& c) const {
    return sizeof(MovingCell) + c.items.capacity() * sizeof(MovingCandidate) +
           (c.final ? 0 : 32 * sizeof(void*));
}

MovingBin::MovingBin(MovingContext& context, float t0, float t1) : context_(context) {
    swept_.reserve(context.moving->size());
    for (std::uint32_t id : *context.moving) swept_.push_back(context.scene->swept_bounds(id, t0, t1));
    space_.origins = context.origins;
    space_.split_origins = true;
    space_.max_depth = context.max_depth;
}

MovingBin::~MovingBin() {
    delete_tree(space_);
    for (auto& b : buffers_) delete_tree(*b);
}

void MovingBin::delete_tree(MovingTree& tree) const {
    for (auto& r : tree.roots) delete_cell(r.exchange(nullptr));
    for (auto& g : tree.grids)
        if (MovingGrid* grid = g.exchange(nullptr)) {
            context_.remove(grid->bytes(), grid->items.size() + grid->wide.size());
            delete grid;
        }
}

void MovingBin::delete_cell(MovingCell* c) const {
    if (!c) return;
    if (!c->final)
        for (int i = 0; i < 32; ++i) delete_cell(c->children[std::size_t(i)].exchange(nullptr));
    context_.remove(bytes_of(*c), c->items.size());
    delete c;
}

namespace {

// A cell's children slots (32 for the 5D tree, 4 for a light buffer; 32 allocated either way).
void open_cell(MovingCell& c) {
    c.children = std::make_unique<std::atomic<MovingCell*>[]>(32);
    for (int i = 0; i < 32; ++i) c.children[std::size_t(i)].store(nullptr, std::memory_order_relaxed);
}

// The cell stored in `slot`, made by `make` when missing (another thread may make it first).
template <class Make, class Delete>
MovingCell* cell_in(std::atomic<MovingCell*>& slot, Make&& make, Delete&& remove) {
    MovingCell* next = slot.load(std::memory_order_acquire);
    if (next) return next;
    MovingCell* made = make();
    MovingCell* expected = nullptr;
    if (slot.compare_exchange_strong(expected, made, std::memory_order_acq_rel, std::memory_order_acquire))
        return made;
    remove(made);
    return expected;
}

}  // namespace

MovingCell* MovingBin::make_root(const MovingTree& tree, int face) const {
    auto root = std::make_unique<MovingCell>();
    for (int k = 0; k < 3; ++k) {
        root->bounds.lo[k] = tree.origins.lower[k];
        root->bounds.hi[k] = tree.origins.upper[k];
    }
    root->bounds.face = face;
    const CellBeam beam = make_cell_beam(root->bounds, context_.origin_margin, context_.direction_margin);
    for (std::size_t i = 0; i < swept_.size(); ++i)
        if (tree.split_origins || box_side(beam, swept_[i]) != BoxSide::outside)
            root->items.push_back(MovingCandidate{swept_[i], key_of(swept_[i], face), std::uint32_t(i)});
    root->items.shrink_to_fit();
    sort_by_key(root->items);
    root->final = root->items.size() <= std::size_t(context_.min_candidates) || tree.max_depth == 0;
    if (!root->final) open_cell(*root);
    context_.add(bytes_of(*root), root->items.size());
    return root.release();
}

MovingCell* MovingBin::make_child(const MovingTree& tree, const MovingCell& parent, int index) const {
    auto c = std::make_unique<MovingCell>();
    c->bounds = child_bounds(parent.bounds, index, tree.split_origins);
    c->depth = parent.depth + 1;
    const CellBeam beam = make_cell_beam(c->bounds, context_.origin_margin, context_.direction_margin);
    for (const MovingCandidate& m : parent.items)
        if (box_side(beam, m.swept) != BoxSide::outside) c->items.push_back(m);
    c->items.shrink_to_fit();
    c->final = c->items.size() <= std::size_t(context_.min_candidates) || c->depth >= tree.max_depth;
    if (!c->final) open_cell(*c);
    context_.add(bytes_of(*c), c->items.size());
    return c.release();
}

namespace {

// Where the directions from any point of `apex` to any point of `box` fall on `face`.
enum class Facing { none, rectangle, straddles };

// The (u, v) rectangle r on `face` of those directions (conservative: padded); none when no such
// direction points into the face's half space, straddles when some do and some do not (the
// rectangle is then unbounded: the whole face).
Facing direction_rectangle(const Box& box, const Box& apex, int face, float r[4]) {
    const int k = face_axis(face), a = (k + 1) % 3, b = (k + 2) % 3;
    const float s = float(face_sign(face));
    const Float3 lo = box.lower - apex.upper, hi = box.upper - apex.lower;  // every difference
    if (s > 0 ? hi[k] <= 0.0f : lo[k] >= 0.0f) return Facing::none;
    if (!(s > 0 ? lo[k] > 0.0f : hi[k] < 0.0f)) return Facing::straddles;
    // u = d[a] / m over the box: m takes its two extremes, d[a] its two; the quotients' extremes are
    // among the four products with the two reciprocals (one more rounding each than a division,
    // far below the padding).
    const float m0 = s * (s > 0 ? lo[k] : hi[k]), m1 = s * (s > 0 ? hi[k] : lo[k]);  // 0 < m0 <= m1
    const float w0 = 1.0f / m0, w1 = 1.0f / m1;
    const auto range = [&](float x0, float x1, float& out_lo, float& out_hi) {
        const float p[4] = {x0 * w0, x0 * w1, x1 * w0, x1 * w1};
        out_lo = std::min(std::min(p[0], p[1]), std::min(p[2], p[3]));
        out_hi = std::max(std::max(p[0], p[1]), std::max(p[2], p[3]));
    };
    range(lo[a], hi[a], r[0], r[1]);
    range(lo[b], hi[b], r[2], r[3]);
    // A linear-fractional map on a box with a positive denominator: extremes at the corners. Padded
    // far above the rounding of a ray's (u, v) and of these quotients.
    for (int i = 0; i < 4; ++i) r[i] += (i % 2 ? 1.0f : -1.0f) * (1e-5f + 1e-5f * std::fabs(r[i]));
    return Facing::rectangle;
}

}  // namespace

MovingGrid* MovingBin::make_grid(const MovingTree& tree, int face) const {
    auto g = std::make_unique<MovingGrid>();
    // About one cell per moving triangle, 4..256 a side. (512 a side, four cells per candidate of a
    // face on `spin`, made the grids slower by more than it saved in tests: docs/raycls.md.)
    int n = 4;
    while (n < 256 && std::size_t(n) * std::size_t(n) < swept_.size()) n *= 2;
    g->n = n;
    const float half = 0.5f * float(n), pad = 1.0f / (64.0f * half);
    const std::size_t wide_cells = std::size_t(n) * std::size_t(n) / 16;
    struct Span {
        int i0, i1, j0, j1;
    };
    // The candidates some direction of the face reaches, each with its cells, sorted by key.
    struct Placed {
        MovingCandidate candidate;
        Span span;
    };
    std::vector<Placed> sorted;
    sorted.reserve(swept_.size());
    for (std::size_t i = 0; i < swept_.size(); ++i) {
        float r[4];
        const Facing facing = direction_rectangle(swept_[i], tree.origins, face, r);
        if (facing == Facing::none) continue;
        Span sp{0, n - 1, 0, n - 1};
        if (facing == Facing::rectangle) {
            if (r[1] < -1.0f - pad || r[0] > 1.0f + pad || r[3] < -1.0f - pad || r[2] > 1.0f + pad) continue;
            const auto cell = [&](float x) { return std::clamp(int(std::floor((x + 1.0f) * half)), 0, n - 1); };
            sp = {cell(r[0] - pad), cell(r[1] + pad), cell(r[2] - pad), cell(r[3] + pad)};
        }
        sorted.push_back(Placed{MovingCandidate{swept_[i], key_of(swept_[i], face), std::uint32_t(i)}, sp});
    }
    if (sorted.empty()) {  // nothing on this face: one empty cell for the rays that take it
        g->n = 1;
        g->offsets.assign(2, 0);
        context_.add(g->bytes(), 0);
        return g.release();
    }
    // In key order, then index order (the candidates were placed in index order): a radix sort of
    // (key, position) words, then the candidates moved into that order.
    {
        std::vector<std::uint64_t> words(sorted.size()), spare;
        for (std::size_t i = 0; i < sorted.size(); ++i)
            words[i] = (std::uint64_t(sortable_bits(sorted[i].candidate.key)) << 32) | std::uint64_t(i);
        radix_sort(words, spare, 64, [](std::uint64_t w) { return w; }, 1);
        std::vector<Placed> ordered(sorted.size());
        for (std::size_t i = 0; i < words.size(); ++i) ordered[i] = sorted[std::size_t(words[i] & 0xFFFFFFFFu)];
        sorted.swap(ordered);
    }
    // Counts shifted by two: after the prefix sums offsets[c + 1] is where cell c starts and serves
    // as its cursor, which ends where cell c + 1 starts; then offsets[c] .. offsets[c + 1] is cell c
    // (no copy of the n x n + 1 offsets).
    const std::size_t cells = std::size_t(n) * std::size_t(n);
    std::vector<std::uint32_t>& offsets = g->offsets;
    offsets.assign(cells + 2, 0);
    for (Placed& p : sorted) {
        Span& sp = p.span;
        if (std::size_t(sp.i1 - sp.i0 + 1) * std::size_t(sp.j1 - sp.j0 + 1) > wide_cells) {
            g->wide.push_back(p.candidate);
            sp = {1, 0, 1, 0};
            continue;
        }
        for (int j = sp.j0; j <= sp.j1; ++j)
            for (int i = sp.i0; i <= sp.i1; ++i) ++offsets[std::size_t(j * n + i) + 2];
    }
    for (std::size_t c = 2; c < offsets.size(); ++c) offsets[c] += offsets[c - 1];
    g->items.resize(offsets.back());
    for (const Placed& p : sorted) {  // in key order: each cell's list stays sorted
        const Span& sp = p.span;
        for (int j = sp.j0; j <= sp.j1; ++j)
            for (int i = sp.i0; i <= sp.i1; ++i) g->items[offsets[std::size_t(j * n + i) + 1]++] = p.candidate;
    }
    offsets.pop_back();
    g->wide.shrink_to_fit();
    context_.add(g->bytes(), g->items.size() + g->wide.size());
    return g.release();
}

const MovingGrid& MovingBin::grid_of(const MovingTree& tree, int face) const {
    auto& slot = const_cast<std::atomic<MovingGrid*>&>(tree.grids[face]);
    MovingGrid* g = slot.load(std::memory_order_acquire);
    if (g) return *g;
    MovingGrid* made = make_grid(tree, face);
    MovingGrid* expected = nullptr;
    if (slot.compare_exchange_strong(expected, made, std::memory_order_acq_rel, std::memory_order_acquire))
        return *made;
    context_.remove(made->bytes(), made->items.size() + made->wide.size());
    delete made;
    return *expected;
}

const MovingTree& MovingBin::light_buffer(const Box& points, float grow) const {
    constexpr std::size_t kMaxBuffers = 16;
    std::lock_guard<std::mutex> lock(buffers_mutex_);
    for (const auto& b : buffers_) {
        if (b->origins.contains(points)) return *b;
    }
    if (buffers_.size() >= kMaxBuffers) return space_;
    auto b = std::make_unique<MovingTree>();
    b->origins = points;
    b->origins.lower = b->origins.lower - Float3{grow, grow, grow};
    b->origins.upper = b->origins.upper + Float3{grow, grow, grow};
    b->split_origins = false;
    buffers_.push_back(std::move(b));
    return *buffers_.back();
}

const MovingCell* MovingBin::cell_of(const MovingTree& tree, const float p[3], const DirectionCode& code) const {
    auto& root_slot = const_cast<std::atomic<MovingCell*>&>(tree.roots[code.face]);
    const auto remove = [this](MovingCell* c) { delete_cell(c); };
    MovingCell* c = cell_in(root_slot, [&] { return make_root(tree, code.face); }, remove);
    while (!c->final) {
        const int index = child_index(c->bounds, p, code.u, code.v, tree.split_origins);
        MovingCell* parent = c;
        c = cell_in(parent->children[std::size_t(index)], [&] { return make_child(tree, *parent, index); }, remove);
    }
    return c;
}

template <bool kAny, bool kCount>
Hit MovingBin::scan(const Ray& ray, float time, const Triangle* placed, Hit best, QueryCounters* counters,
                    const MovingTree& tree, Frame frame) const {
    if (!describes_segment(ray)) return best;
    float p[3] = {0.0f, 0.0f, 0.0f};  // not read by a light buffer (its origins are not split)
    DirectionCode code;
    if (frame == Frame::space) {
        // The part of the segment inside the scene's box, classified from where it enters.
        const Box& box = tree.origins;
        const Float3 inv{1.0f / ray.dir.x, 1.0f / ray.dir.y, 1.0f / ray.dir.z};
        float tmin, tmax;
        if (!kdtree::clip_to_box(ray, inv, box, tmin, tmax)) return best;
        for (int k = 0; k < 3; ++k) p[k] = std::clamp(ray.org[k] + tmin * ray.dir[k], box.lower[k], box.upper[k]);
        code = direction_code(ray.dir);
    } else if (frame == Frame::from_start) {
        code = direction_code(ray.dir);
    } else {
        code = direction_code(Float3{-ray.dir.x, -ray.dir.y, -ray.dir.z});
    }
    // A light buffer's cell, found before any set-up: most rays meet an empty one.
    std::span<const MovingCandidate> cell_items;
    const MovingGrid* grid = nullptr;
    if (!tree.split_origins) {
        grid = &grid_of(tree, code.face);
        const int c = grid->index(code.u, code.v);
        cell_items = {grid->items.data() + grid->offsets[std::size_t(c)],
                      grid->items.data() + grid->offsets[std::size_t(c) + 1]};
        if (cell_items.empty() && grid->wide.empty()) return best;
    }
    const int k = face_axis(code.face);
    const float key_origin = float(face_sign(code.face)) * ray.org[k];
    const float step = std::fabs(ray.dir[k]);
    WatertightRay w = make_watertight_ray(ray);
    if (best.hit()) w.tfar = best.t;
    // Seen from the light, the segment ends where the ray starts.
    const auto stop_at = [&](const Hit& h) {
        return frame == Frame::from_end ? key_stop(key_origin, -ray.tnear, step)
                                        : key_stop(key_origin, h.hit() ? h.t : ray.tfar, step);
    };
    // One key-sorted list; false when an occlusion hit ended the search.
    const auto scan_list = [&](std::span<const MovingCandidate> items) {
        float stop = stop_at(best);
        Triangle tris[8];
        const Triangle* batch[8];
        for (std::size_t first = 0; first < items.size(); first += 8) {
            if (items[first].key > stop) break;
            LaneHits lanes;
            const int count = test_at_time(context_, w, items, first, time, placed, tris, batch, lanes);
            if constexpr (kCount) counters->triangle_tests += std::uint64_t(count);
            for (std::uint32_t m = lanes.mask; m; m &= m - 1) {
                const int j = __builtin_ctz(m);
                const std::uint32_t id = (*context_.moving)[items[first + std::size_t(j)].index];
                if (!(lanes.t[j] < best.t || (lanes.t[j] == best.t && id < best.triangle))) continue;
                if (zero_area(*batch[j])) continue;
                best = Hit{lanes.t[j], id, lanes.u[j], lanes.v[j]};
                if constexpr (kAny) return false;
                w.tfar = best.t;
                stop = stop_at(best);
            }
        }
        return true;
    };
    if (tree.split_origins) {
        scan_list(cell_of(tree, p, code)->items);
        return best;
    }
    if (scan_list(cell_items)) scan_list(grid->wide);
    return best;
}

template <bool kCount>
Hit MovingBin::closest(const Ray& ray, float time, const Triangle* placed, Hit best, QueryCounters* counters,
                       const MovingTree& tree, Frame frame) const {
    return scan<false, kCount>(ray, time, placed, best, counters, tree, frame);
}

template <bool kCount>
bool MovingBin::any(const Ray& ray, float time, const Triangle* placed, QueryCounters* counters,
                    const MovingTree& tree, Frame frame) const {
    return scan<true, kCount>(ray, time, placed, Hit{}, counters, tree, frame).hit();
}

template Hit MovingBin::closest<true>(const Ray&, float, const Triangle*, Hit, QueryCounters*, const MovingTree&,
                                      Frame) const;
template Hit MovingBin::closest<false>(const Ray&, float, const Triangle*, Hit, QueryCounters*, const MovingTree&,
                                       Frame) const;
template bool MovingBin::any<true>(const Ray&, float, const Triangle*, QueryCounters*, const MovingTree&, Frame) const;
template bool MovingBin::any<false>(const Ray&, float, const Triangle*, QueryCounters*, const MovingTree&,
                                    Frame) const;

}  // namespace beamtrace::raycls
