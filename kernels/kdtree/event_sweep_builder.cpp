#include "kdtree/event_sweep_builder.hpp"

#include <algorithm>

namespace beamtrace::kd {

namespace {

enum Side : std::uint8_t { kLeft = 0, kRight = 1, kBoth = 2 };

std::size_t triangles_in(const AxisEvents& events) {
    std::size_t n = 0;
    for (const SplitEvent& e : events) n += e.type() != kEnd;
    return n;
}

}  // namespace

EventSweepBuilder::EventSweepBuilder(BuildContext& context)
    : context_(context), side_(context.scene().triangle_count(), kBoth) {}

void EventSweepBuilder::sort(AxisEvents (&events)[3]) {
    for (auto& e : events) sort_events(e, scratch_);
}

void EventSweepBuilder::build(const Box& box, AxisEvents (&events)[3], std::size_t n, int depth) {
    auto leaf = [&] {
        context_.make_leaf(box, [&](std::vector<std::uint32_t>& ids) {
            for (const SplitEvent& e : events[0])
                if (e.type() != kEnd) ids.push_back(e.tri());
        });
    };
    if (context_.stops_here(box, n, depth)) return leaf();
    const SplitChoice split = find_split(box, events, n);
    if (split.axis < 0) return leaf();

    Box left = box, right = box;
    left.upper[split.axis] = split.pos;
    right.lower[split.axis] = split.pos;
    AxisEvents left_events[3], right_events[3];
    partition(split, left, right, events, left_events, right_events);
    const std::size_t nl = triangles_in(left_events[0]), nr = triangles_in(right_events[0]);
    context_.make_inner(
        split, box,
        [&] {
            build(left, left_events, nl, depth + 1);
            for (auto& e : left_events) AxisEvents().swap(e);
        },
        [&] { build(right, right_events, nr, depth + 1); });
}

SplitChoice EventSweepBuilder::find_split(const Box& box, const AxisEvents (&events)[3], std::size_t n) const {
    Box tight;  // the first and last events of each axis
    for (int k = 0; k < 3; ++k) {
        tight.lower[k] = events[k].front().pos;
        tight.upper[k] = events[k].back().pos;
    }
    if (const SplitChoice cut = empty_cell_cut(context_.rules(), box, tight); cut.axis >= 0) return cut;

    const float area = box.surface_area();
    SplitSearch search(context_.rules());
    for (int k = 0; k < 3; ++k) {
        const AxisCell cell(box, k, area);
        if (!cell.splittable()) continue;
        const AxisEvents& ev = events[k];
        std::size_t nl = 0, nr = n;
        std::size_t i = 0;
        while (i < ev.size()) {
            const float p = ev[i].pos;
            std::size_t ends = 0, planars = 0, starts = 0;
            while (i < ev.size() && ev[i].pos == p && ev[i].type() == kEnd) ++ends, ++i;
            const std::size_t planar_begin = i;
            while (i < ev.size() && ev[i].pos == p && ev[i].type() == kPlanar) ++planars, ++i;
            const std::size_t planar_end = i;
            while (i < ev.size() && ev[i].pos == p && ev[i].type() == kStart) ++starts, ++i;
            nr -= planars + ends;
            search.consider(cell, p, nl, planars, nr, [&] {
                return context_.covered(
                    ev.begin() + std::ptrdiff_t(planar_begin), ev.begin() + std::ptrdiff_t(planar_end),
                    [](const SplitEvent& e) { return e.tri(); }, box, k, cell.cross_section);
            });
            nl += starts + planars;
        }
    }
    return search.choice(n);
}

void EventSweepBuilder::partition(const SplitChoice& s, const Box& left, const Box& right, AxisEvents (&events)[3],
                                  AxisEvents (&left_events)[3], AxisEvents (&right_events)[3]) {
    if (s.rule == Rule::empty_cell) {  // every triangle on the side the plane's triangles go to
        for (int k = 0; k < 3; ++k) (s.planar_left ? left_events : right_events)[k] = std::move(events[k]);
        return;
    }
    // One pass over the split axis classifies every triangle: a start at or above the plane is
    // right only, an end at or below it left only (its start came earlier), otherwise both;
    // triangles still "both" at their end event straddle the plane.
    both_.clear();
    for (const SplitEvent& e : events[s.axis]) {
        const std::uint32_t t = e.tri();
        switch (e.type()) {
            case kStart:
                side_[t] = e.pos >= s.pos ? kRight : kBoth;
                break;
            case kPlanar:
                side_[t] = (e.pos < s.pos || (e.pos == s.pos && s.planar_left)) ? kLeft : kRight;
                break;
            case kEnd:
                if (e.pos <= s.pos)
                    side_[t] = kLeft;
                else if (side_[t] == kBoth)
                    both_.push_back(t);
                break;
        }
    }
    for (int k = 0; k < 3; ++k) {
        left_events[k].reserve(events[k].size() / 2 + 2 * both_.size());
        right_events[k].reserve(events[k].size() / 2 + 2 * both_.size());
        for (const SplitEvent& e : events[k]) {
            if (side_[e.tri()] == kLeft)
                left_events[k].push_back(e);
            else if (side_[e.tri()] == kRight)
                right_events[k].push_back(e);
        }
        AxisEvents().swap(events[k]);
    }
    if (both_.empty()) return;
    AxisEvents new_left[3], new_right[3];
    for (std::uint32_t t : both_) {
        const Triangle& tri = context_.scene().triangle(t);
        const Box bl = clipped_bounds(tri, left, context_.slack());
        if (!bl.empty()) append_events(t, bl, new_left);
        const Box br = clipped_bounds(tri, right, context_.slack());
        if (!br.empty()) append_events(t, br, new_right);
    }
    for (int k = 0; k < 3; ++k) {
        merge_into(left_events[k], new_left[k]);
        merge_into(right_events[k], new_right[k]);
    }
}

void EventSweepBuilder::merge_into(AxisEvents& kept, AxisEvents& added) {
    if (added.empty()) return;
    sort_events(added, scratch_);
    const std::size_t mid = kept.size();
    kept.insert(kept.end(), added.begin(), added.end());
    std::inplace_merge(kept.begin(), kept.begin() + std::ptrdiff_t(mid), kept.end());
}

}  // namespace beamtrace::kd
