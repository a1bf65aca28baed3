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
        return a.key < b.key || (a.key == b.key && a.id < b.id);
    });
}

// Up to eight candidates from `first`, placed at `time`, against the ray.
int test_at_time(const MovingContext& c, const WatertightRay& w, const std::vector<MovingCandidate>& items,
                 std::size_t first, float time, Triangle (&tris)[8], LaneHits& lanes) {
    const int count = int(std::min<std::size_t>(8, items.size() - first));
    const Triangle* batch[8];
    for (int j = 0; j < count; ++j) {
        tris[j] = c.scene->triangle_at(items[first + std::size_t(j)].id, time);
        batch[j] = &tris[j];
    }
    if (count <= 4)
        c.kernels->ray_x4(w, batch, count, lanes);
    else
        c.kernels->ray_x8(w, batch, count, lanes);
    return count;
}

}  // namespace

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
    std::vector<Box> swept;
    swept.reserve(context.moving->size());
    for (std::uint32_t id : *context.moving) swept.push_back(context.scene->swept_bounds(id, t0, t1));
    for (int f = 0; f < 6; ++f) {
        auto root = std::make_unique<MovingCell>();
        for (int k = 0; k < 3; ++k) {
            root->bounds.lo[k] = context.origins.lower[k];
            root->bounds.hi[k] = context.origins.upper[k];
        }
        root->bounds.face = f;
        root->items.reserve(swept.size());
        for (std::size_t i = 0; i < swept.size(); ++i)
            root->items.push_back(MovingCandidate{swept[i], key_of(swept[i], f), (*context.moving)[i]});
        sort_by_key(root->items);
        root->final = root->items.size() <= std::size_t(context.min_candidates) || context.max_depth == 0;
        if (!root->final) {
            root->children = std::make_unique<std::atomic<MovingCell*>[]>(32);
            for (int i = 0; i < 32; ++i) root->children[std::size_t(i)].store(nullptr, std::memory_order_relaxed);
        }
        context_.add(bytes_of(*root), root->items.size());
        roots_[f] = std::move(root);
    }
}

MovingBin::~MovingBin() {
    for (auto& r : roots_) delete_cell(r.release());
}

void MovingBin::delete_cell(MovingCell* c) const {
    if (!c) return;
    if (!c->final)
        for (int i = 0; i < 32; ++i) delete_cell(c->children[std::size_t(i)].exchange(nullptr));
    context_.remove(bytes_of(*c), c->items.size());
    delete c;
}

MovingCell* MovingBin::make_child(const MovingCell& parent, int index) const {
    auto c = std::make_unique<MovingCell>();
    c->bounds = child_bounds(parent.bounds, index, true);
    c->depth = parent.depth + 1;
    const CellBeam beam = make_cell_beam(c->bounds, context_.origin_margin, context_.direction_margin);
    for (const MovingCandidate& m : parent.items)
        if (box_side(beam, m.swept) != BoxSide::outside) c->items.push_back(m);
    c->items.shrink_to_fit();
    c->final = c->items.size() <= std::size_t(context_.min_candidates) || c->depth >= context_.max_depth;
    if (!c->final) {
        c->children = std::make_unique<std::atomic<MovingCell*>[]>(32);
        for (int i = 0; i < 32; ++i) c->children[std::size_t(i)].store(nullptr, std::memory_order_relaxed);
    }
    context_.add(bytes_of(*c), c->items.size());
    return c.release();
}

const MovingCell* MovingBin::cell_of(const Ray& r, float& key_origin, float& step) const {
    const Box& box = context_.origins;
    const Float3 inv{1.0f / r.dir.x, 1.0f / r.dir.y, 1.0f / r.dir.z};
    float tmin, tmax;
    if (!kdtree::clip_to_box(r, inv, box, tmin, tmax)) return nullptr;
    float p[3];
    for (int k = 0; k < 3; ++k) p[k] = std::clamp(r.org[k] + tmin * r.dir[k], box.lower[k], box.upper[k]);
    const DirectionCode code = direction_code(r.dir);
    MovingCell* c = roots_[code.face].get();
    while (!c->final) {
        std::atomic<MovingCell*>& slot = c->children[std::size_t(child_index(c->bounds, p, code.u, code.v, true))];
        MovingCell* next = slot.load(std::memory_order_acquire);
        if (!next) {
            MovingCell* made = make_child(*c, int(&slot - &c->children[0]));
            MovingCell* expected = nullptr;
            if (slot.compare_exchange_strong(expected, made, std::memory_order_acq_rel, std::memory_order_acquire)) {
                next = made;
            } else {
                delete_cell(made);  // another thread made the same cell first
                next = expected;
            }
        }
        c = next;
    }
    const int k = face_axis(code.face);
    key_origin = float(face_sign(code.face)) * r.org[k];
    step = std::fabs(r.dir[k]);
    return c;
}

template <bool kAny, bool kCount>
Hit MovingBin::scan(const Ray& ray, float time, Hit best, QueryCounters* counters) const {
    if (!describes_segment(ray)) return best;
    float key_origin = 0.0f, step = 0.0f;
    const MovingCell* cell = cell_of(ray, key_origin, step);
    if (!cell) return best;
    WatertightRay w = make_watertight_ray(ray);
    if (best.hit()) w.tfar = best.t;
    float stop = key_stop(key_origin, best.hit() ? best.t : ray.tfar, step);
    Triangle tris[8];
    for (std::size_t first = 0; first < cell->items.size(); first += 8) {
        if (cell->items[first].key > stop) break;
        LaneHits lanes;
        const int count = test_at_time(context_, w, cell->items, first, time, tris, lanes);
        if constexpr (kCount) counters->triangle_tests += std::uint64_t(count);
        for (std::uint32_t m = lanes.mask; m; m &= m - 1) {
            const int j = __builtin_ctz(m);
            const std::uint32_t id = cell->items[first + std::size_t(j)].id;
            if (!(lanes.t[j] < best.t || (lanes.t[j] == best.t && id < best.triangle))) continue;
            if (zero_area(tris[j])) continue;
            best = Hit{lanes.t[j], id, lanes.u[j], lanes.v[j]};
            if constexpr (kAny) return best;
            w.tfar = best.t;
            stop = key_stop(key_origin, best.t, step);
        }
    }
    return best;
}

template <bool kCount>
Hit MovingBin::closest(const Ray& ray, float time, Hit best, QueryCounters* counters) const {
    return scan<false, kCount>(ray, time, best, counters);
}

template <bool kCount>
bool MovingBin::any(const Ray& ray, float time, QueryCounters* counters) const {
    return scan<true, kCount>(ray, time, Hit{}, counters).hit();
}

template Hit MovingBin::closest<true>(const Ray&, float, Hit, QueryCounters*) const;
template Hit MovingBin::closest<false>(const Ray&, float, Hit, QueryCounters*) const;
template bool MovingBin::any<true>(const Ray&, float, QueryCounters*) const;
template bool MovingBin::any<false>(const Ray&, float, QueryCounters*) const;

}  // namespace beamtrace::raycls
