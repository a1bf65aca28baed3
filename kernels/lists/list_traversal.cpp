// The paper's ray traversal of a hierarchy of sorted lists, with its CPU replacements (notes 1.4):
//
// - Each event gets a *key*: its ray parameter t = (value - org) / dir (a quotient), moved earlier
//   by a slack for an IN event and later for an OUT event (slack(t) below), so that rounding can
//   only make a box look larger: a box the exact ray touches is always entered, and every triangle
//   the watertight test hits is tested. Because the slack differs for IN and OUT, each axis list is read as its two
//   sorted halves (IN: the lower coordinates ascending when dir > 0, the upper ones descending when
//   dir < 0; OUT the other half), each with keys in ray order. An axis with dir == 0 has no events in
//   ray order: its IN keys are -inf (lower <= org) or +inf, its OUT keys -inf (upper < org) or +inf,
//   which fixes each box's status on that axis when its volume is opened (exact, as the kd-tree).
// - The "list of next events" is one binary heap over the cursors of every open volume's runs,
//   smallest key first; at equal keys IN before OUT (a ray touching a box at one point enters it) and
//   a deeper volume's OUT before a shallower one's (a volume's children are closed before it).
//   Cursors of a closed volume are dropped when they come up (lazy deletion).
// - Per-ray marks (IN count, processed) live in per-thread arrays reset by a stamp per ray.
// - Opening a volume at key k walks its children's events with keys below k on every axis (the
//   paper's walk of the other axes; for the root or a volume holding the ray's start, every axis:
//   the paper's per-image "camera ray list", here per ray), then activates the children entered on
//   all three axes by then; only the runs' remaining events go to the heap.
// - Termination: the next key beyond the closest hit (with slack), tfar or the root's exit; occlusion:
//   the first hit.
#include "lists/list_traversal.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "common/ray_validity.hpp"
#include "common/triangle_reference.hpp"

namespace beamtrace::lists {
namespace {

constexpr float kRelativeSlack = 1.0f / 1048576.0f;  // as the kd-tree's (kdtree/ray_traversal.hpp)

struct ItemState {
    std::uint32_t stamp = 0;
    std::uint16_t in = 0;         // IN events seen (3: entered on every axis; 4: activated)
    std::uint16_t processed = 0;  // an OUT event seen: the ray has left the box
};

struct Cursor {
    const Event* run;
    std::uint32_t count, next;  // events in the run, the next one's rank in ray order
    std::uint32_t volume;       // the owning volume's item
    std::uint8_t axis, out, descending;
    std::uint32_t order;  // tie order of its events in the heap

    const Event& at(std::uint32_t i) const { return descending ? run[count - 1 - i] : run[i]; }
};

struct HeapEntry {
    float key;
    std::uint32_t order;
    std::uint32_t cursor;
};

// Heap order: the entry that comes later is "less" (std heaps keep the greatest on top). A function
// object, so that the heap's sift loops inline it.
struct Later {
    bool operator()(const HeapEntry& a, const HeapEntry& b) const {
        return a.key > b.key || (a.key == b.key && a.order > b.order);
    }
};
constexpr Later later{};

// Per-thread scratch, reused by every ray of the thread (any SortedLists: items are stamped per ray).
struct Scratch {
    std::vector<ItemState> state;
    std::uint32_t stamp = 0;
    std::vector<HeapEntry> heap;
    std::vector<Cursor> cursors;
    std::vector<std::uint32_t> candidates;

    void begin_ray(std::uint32_t items) {
        if (state.size() < items) state.resize(items);
        if (++stamp == 0) {
            std::fill(state.begin(), state.end(), ItemState{});
            stamp = 1;
        }
        heap.clear();
        cursors.clear();
        candidates.clear();
    }
};

Scratch& scratch() {
    thread_local Scratch s;
    return s;
}

template <bool kOcclusion, bool kCount>
class Traversal {
public:
    Traversal(const SortedLists::Impl& impl, const Ray& ray, QueryCounters* counters)
        : impl_(impl), ray_(ray), counters_(counters), s_(scratch()), w_(make_watertight_ray(ray)) {
        s_.begin_ray(impl.item_count());
        // Absolute slack: the watertight test's t carries rounding of the order of the coordinates'
        // magnitude relative to the origin (divided by the dominant direction component), so a hit
        // at t near 0 can be computed slightly before its box's entry.
        const Box& root = impl.volumes[0].box;
        float reach = 0.0f, dmax = 0.0f;
        for (int a = 0; a < 3; ++a) {
            reach += std::max(std::fabs(root.lower[a] - ray.org[a]), std::fabs(root.upper[a] - ray.org[a]));
            dmax = std::max(dmax, std::fabs(ray.dir[a]));
            sign_[a] = ray.dir[a] > 0.0f ? 1 : (ray.dir[a] < 0.0f ? -1 : 0);
        }
        absolute_ = reach * kRelativeSlack / dmax;
        limit_ = late(ray.tfar);
    }

    Hit run() {
        const Volume& root = impl_.volumes[0];
        if (root.children == 0) return best_;
        // The root has no parent lists: its entry and exit keys from its box.
        float enter = early(ray_.tnear), leave = kInfinity;
        for (int a = 0; a < 3; ++a) {
            enter = std::max(enter, in_key(a, sign_[a] < 0 ? root.box.upper[a] : root.box.lower[a]));
            leave = std::min(leave, out_key(a, sign_[a] < 0 ? root.box.lower[a] : root.box.upper[a]));
        }
        if (!(enter <= leave) || !(enter <= limit_) || enter == kInfinity) return best_;
        // Past the root's exit every child has been left on some axis (the paper's "end of one of
        // the lists reached"): no event there can matter.
        limit_ = std::min(limit_, leave);
        open(0, enter);
        while (!done_ && !s_.heap.empty()) {
            const HeapEntry top = s_.heap.front();
            if (top.key > limit_) break;
            if constexpr (kCount) ++counters_->lists.heap_ops;
            Cursor& c = s_.cursors[top.cursor];
            if (state(c.volume).processed) {  // a closed volume's run: dropped
                pop_top();
                continue;
            }
            const Event e = c.at(c.next++);
            const bool out = c.out != 0;
            const float next = c.next < c.count ? key_of(c, c.at(c.next).value) : kInfinity;
            if (next != kInfinity) {  // the cursor's next event takes its place (one sift instead of two)
                if constexpr (kCount) ++counters_->lists.heap_ops;
                replace_top(HeapEntry{next, top.order, top.cursor});
            } else {
                pop_top();
            }
            if constexpr (kCount) ++counters_->lists.events;
            treat(e.item, out, top.key);
        }
        return best_;
    }

private:
    // The key of an IN event (earlier than its t) and of an OUT event (later). t is a quotient, not a
    // product with 1 / dir: a denormal dir component has no finite reciprocal, and an event at the
    // origin's coordinate would give 0 * inf = NaN (a sign's worth of exact t is all that is needed).
    float early(float t) const { return std::isinf(t) ? t : t - (std::fabs(t) * kRelativeSlack + absolute_); }
    float late(float t) const { return std::isinf(t) ? t : t + (std::fabs(t) * kRelativeSlack + absolute_); }
    float in_key(int a, float value) const {
        if (sign_[a] == 0) return value <= ray_.org[a] ? -kInfinity : kInfinity;
        return early((value - ray_.org[a]) / ray_.dir[a]);
    }
    float out_key(int a, float value) const {
        if (sign_[a] == 0) return value < ray_.org[a] ? -kInfinity : kInfinity;
        return late((value - ray_.org[a]) / ray_.dir[a]);
    }
    float key_of(const Cursor& c, float value) const { return c.out ? out_key(c.axis, value) : in_key(c.axis, value); }

    ItemState& state(std::uint32_t item) {
        ItemState& st = s_.state[item];
        if (st.stamp != s_.stamp) st = ItemState{s_.stamp, 0, 0};
        return st;
    }

    // The heap's top replaced by x, sifted down.
    void replace_top(const HeapEntry& x) {
        std::vector<HeapEntry>& h = s_.heap;
        const std::size_t n = h.size();
        std::size_t i = 0;
        for (;;) {
            std::size_t child = 2 * i + 1;
            if (child >= n) break;
            if (child + 1 < n && later(h[child], h[child + 1])) ++child;  // the earlier child
            if (!later(x, h[child])) break;
            h[i] = h[child];
            i = child;
        }
        h[i] = x;
    }
    void pop_top() {
        const HeapEntry last = s_.heap.back();
        s_.heap.pop_back();
        if (!s_.heap.empty()) replace_top(last);
    }

    void push(std::uint32_t cursor, float key) {
        s_.heap.push_back(HeapEntry{key, s_.cursors[cursor].order, cursor});
        std::push_heap(s_.heap.begin(), s_.heap.end(), later);
        if constexpr (kCount) ++counters_->lists.heap_ops;
    }

    // An event in ray order at key k.
    void treat(std::uint32_t item, bool out, float k) {
        ItemState& st = state(item);
        if (st.processed) return;
        if (out) {
            st.processed = 1;
            return;
        }
        if (++st.in == 3) {
            st.in = 4;
            activate(item, k);
        }
    }

    // A child entered on every axis at key k: a triangle is tested, a volume opened.
    void activate(std::uint32_t item, float k) {
        if (item >= impl_.triangle_count) {
            open(item - impl_.triangle_count, k);
            return;
        }
        if constexpr (kCount) ++counters_->triangle_tests;
        TriangleHit h;
        if (!intersect_triangle(w_, impl_.scene.triangle(item), h)) return;
        if constexpr (kOcclusion) {
            best_ = Hit{h.t, item, h.u, h.v};
            done_ = true;
        } else if (h.t < best_.t || (h.t == best_.t && item < best_.triangle)) {
            best_ = Hit{h.t, item, h.u, h.v};
            w_.tfar = h.t;
            limit_ = std::min(limit_, late(h.t));
        }
    }

    // Opens volume v at key k: walks its runs below k, activates what that entered, queues the rest.
    void open(std::uint32_t v, float k) {
        const Volume& vol = impl_.volumes[v];
        if constexpr (kCount) ++counters_->lists.volumes_opened;
        const std::size_t first_candidate = s_.candidates.size();
        for (int a = 0; a < 3; ++a)
            for (int out = 0; out < 2; ++out) {
                // IN: the lower coordinates ascending (dir > 0 or == 0) or the upper ones descending.
                const int upper = (sign_[a] < 0) != (out != 0) ? 1 : 0;
                Cursor c{impl_.events.data() + vol.run(a, upper),
                         vol.children,
                         0,
                         impl_.triangle_count + v,
                         std::uint8_t(a),
                         std::uint8_t(out),
                         std::uint8_t(sign_[a] < 0 ? 1 : 0),
                         out ? 1u + (255u - std::min<std::uint32_t>(vol.depth, 255u)) : 0u};
                float key = kInfinity;
                for (; c.next < c.count; ++c.next) {
                    const Event& e = c.at(c.next);
                    key = key_of(c, e.value);
                    if (!(key < k)) break;
                    if constexpr (kCount) {
                        ++counters_->lists.events;
                        ++counters_->lists.walked_events;
                    }
                    ItemState& st = state(e.item);
                    if (out)
                        st.processed = 1;
                    else if (++st.in == 3)
                        s_.candidates.push_back(e.item);
                }
                if (c.next < c.count && key != kInfinity) {
                    s_.cursors.push_back(c);
                    push(std::uint32_t(s_.cursors.size() - 1), key);
                }
            }
        // The children the walk entered on every axis (and did not leave): entered at k.
        for (std::size_t i = first_candidate; i < s_.candidates.size() && !done_; ++i) {
            const std::uint32_t item = s_.candidates[i];
            ItemState& st = state(item);
            if (st.in == 3 && !st.processed) {
                st.in = 4;
                activate(item, k);  // may open volumes, which push and pop their own candidates
            }
        }
        s_.candidates.resize(first_candidate);
    }

    const SortedLists::Impl& impl_;
    const Ray& ray_;
    QueryCounters* counters_;
    Scratch& s_;
    WatertightRay w_;
    int sign_[3];
    float absolute_ = 0.0f;
    float limit_ = kInfinity;  // keys beyond this cannot matter (tfar, then the closest hit, with slack)
    Hit best_;
    bool done_ = false;
};

}  // namespace

template <bool kOcclusion, bool kCount>
Hit trace_ray(const SortedLists::Impl& impl, const Ray& ray, QueryCounters* counters) {
    if constexpr (kCount) ++counters->rays;
    if (!describes_segment(ray) || impl.volumes.empty()) return Hit{};
    return Traversal<kOcclusion, kCount>(impl, ray, counters).run();
}

template Hit trace_ray<false, false>(const SortedLists::Impl&, const Ray&, QueryCounters*);
template Hit trace_ray<false, true>(const SortedLists::Impl&, const Ray&, QueryCounters*);
template Hit trace_ray<true, false>(const SortedLists::Impl&, const Ray&, QueryCounters*);
template Hit trace_ray<true, true>(const SortedLists::Impl&, const Ray&, QueryCounters*);

}  // namespace beamtrace::lists
