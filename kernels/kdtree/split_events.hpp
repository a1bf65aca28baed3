#pragma once
// Split candidates of the O(N log N) SAH build (Wald & Havran 2006): per axis, the start, end and
// planar events of each triangle's clipped box, sorted by position then type.
#include <cstdint>
#include <vector>

#include "beamtrace/scene.hpp"

namespace beamtrace::kd {

enum EventType : std::uint8_t { kEnd = 0, kPlanar = 1, kStart = 2 };

// 8 bytes: position, and the event type in the top two bits above a 30-bit triangle id, so that
// ordering by (pos, key) orders by position, then type (end < planar < start).
struct SplitEvent {
    float pos;
    std::uint32_t key;

    static constexpr std::uint32_t kMaxTriangle = (1u << 30) - 1;

    SplitEvent() = default;
    SplitEvent(float p, std::uint32_t tri, EventType type) : pos(p), key((std::uint32_t(type) << 30) | tri) {}
    std::uint32_t tri() const { return key & kMaxTriangle; }
    EventType type() const { return EventType(key >> 30); }

    friend bool operator<(const SplitEvent& a, const SplitEvent& b) {
        return a.pos < b.pos || (a.pos == b.pos && a.key < b.key);
    }
};
static_assert(sizeof(SplitEvent) == 8);

using AxisEvents = std::vector<SplitEvent>;

// Sorts events by operator< (position, then type, then triangle). Long lists by a radix sort of an
// order-preserving 64-bit key (-0 taken as +0, as operator< does), short ones by std::sort: the
// keys are unique, so both give the one order std::sort gives. `scratch` is reused across calls.
void sort_events(AxisEvents& events, AxisEvents& scratch);

// Box of the part of `tri` inside `cell`, computed in double precision against the cell grown by
// `slack` and rounded outwards, then limited to `cell`: never smaller than the exact part, so no
// ray can miss the triangle because of clipping. Empty if the triangle stays out of the grown cell.
Box clipped_bounds(const Triangle& tri, const Box& cell, double slack);

// Appends the events of one triangle with box b (already inside the cell) to the three axes.
void append_events(std::uint32_t tri, const Box& b, AxisEvents (&events)[3]);

// Area of the part of a triangle lying in the plane axis = pos that falls inside the cell's face.
double clipped_planar_area(const Triangle& tri, const Box& cell, int axis);

}  // namespace beamtrace::kd
