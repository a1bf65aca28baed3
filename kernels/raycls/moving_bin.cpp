// The moving triangles over one time bin (moving_bin.hpp).
#include "raycls/moving_bin.hpp"

#include <algorithm>
#include <cmath>

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
int test_at_time(const MovingContext& c, const WatertightRay& w, const std::vector<MovingCandidate>& items,
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

const MovingTree& MovingBin::light_buffer(const Box& points, float grow) const {
    constexpr std::size_t kMaxBuffers = 16;
    std::lock_guard<std::mutex> lock(buffers_mutex_);
    for (const auto& b : buffers_) {
        const Box& o = b->origins;
        if (o.lower.x <= points.lower.x && o.lower.y <= points.lower.y && o.lower.z <= points.lower.z &&
            o.upper.x >= points.upper.x && o.upper.y >= points.upper.y && o.upper.z >= points.upper.z)
            return *b;
    }
    if (buffers_.size() >= kMaxBuffers) return space_;
    auto b = std::make_unique<MovingTree>();
    b->origins = points;
    b->origins.lower = b->origins.lower - Float3{grow, grow, grow};
    b->origins.upper = b->origins.upper + Float3{grow, grow, grow};
    b->split_origins = false;
    b->max_depth = context_.light_depth;
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
    const MovingCell* cell = cell_of(tree, p, code);
    const int k = face_axis(code.face);
    const float key_origin = float(face_sign(code.face)) * ray.org[k];
    const float step = std::fabs(ray.dir[k]);
    WatertightRay w = make_watertight_ray(ray);
    if (best.hit()) w.tfar = best.t;
    // Seen from the light, the segment ends where the ray starts.
    float stop = frame == Frame::from_end ? key_stop(key_origin, -ray.tnear, step)
                                          : key_stop(key_origin, best.hit() ? best.t : ray.tfar, step);
    Triangle tris[8];
    const Triangle* batch[8];
    for (std::size_t first = 0; first < cell->items.size(); first += 8) {
        if (cell->items[first].key > stop) break;
        LaneHits lanes;
        const int count = test_at_time(context_, w, cell->items, first, time, placed, tris, batch, lanes);
        if constexpr (kCount) counters->triangle_tests += std::uint64_t(count);
        for (std::uint32_t m = lanes.mask; m; m &= m - 1) {
            const int j = __builtin_ctz(m);
            const std::uint32_t id = (*context_.moving)[cell->items[first + std::size_t(j)].index];
            if (!(lanes.t[j] < best.t || (lanes.t[j] == best.t && id < best.triangle))) continue;
            if (zero_area(*batch[j])) continue;
            best = Hit{lanes.t[j], id, lanes.u[j], lanes.v[j]};
            if constexpr (kAny) return best;
            w.tfar = best.t;
            if (frame != Frame::from_end) stop = key_stop(key_origin, best.t, step);
        }
    }
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
