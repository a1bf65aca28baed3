#pragma once
// Choosing a node's split plane among candidate planes: the SAH cost of a plane (Wald & Havran
// 2006, with their bonus for an empty side) and MLRTA's rules 1 and 2 (section 3.1) over the
// candidates. Shared by the exact event sweep (every event position a candidate) and the binned
// upper levels (bin boundaries and the references' tight bounds as candidates).
#include <cmath>
#include <cstddef>

#include "beamtrace/kdtree.hpp"
#include "beamtrace/scene.hpp"

namespace beamtrace::kd {

enum class Rule { sah, empty_cell, flat_cell };

struct SplitChoice {
    int axis = -1;
    float pos = 0.0f;
    bool planar_left = false;  // triangles lying in the plane go to the lower child
    float cost = INFINITY;
    Rule rule = Rule::sah;
};

// Bonus of the classic SAH for splits with an empty side (Wald & Havran's lambda).
constexpr float kEmptySideBonus = 0.8f;

// The cell seen along one axis: child areas relative to the cell's are a linear function of the
// plane's position (length along the axis times a, plus b).
struct AxisCell {
    int axis = 0;
    float lo = 0.0f, hi = 0.0f;
    float a = 0.0f, b = 0.0f;
    double cross_section = 0.0;  // area of the cell's face normal to the axis

    AxisCell(const Box& cell, int k, float area) : axis(k), lo(cell.lower[k]), hi(cell.upper[k]) {
        const int u = (k + 1) % 3, v = (k + 2) % 3;
        const float eu = cell.upper[u] - cell.lower[u], ev = cell.upper[v] - cell.lower[v];
        cross_section = double(eu) * double(ev);
        a = 2.0f * (eu + ev) / area;
        b = 2.0f * eu * ev / area;
    }
    bool splittable() const { return hi > lo; }  // flat along the axis: no plane splits it
};

// The best candidates seen so far, one per rule; choice() applies the rules' order.
class SplitSearch {
public:
    explicit SplitSearch(const KdBuildRules& rules) : rules_(rules) { best_empty_.cost = 0.0f; }

    // A plane at p with nl triangles only below it, np lying in it and nr only above it (those
    // crossing it counted on both sides). `covered()` says whether the np triangles in the plane
    // cover the cell's face (MLRTA rule 2); it is asked only when that could decide.
    template <class Covered>
    void consider(const AxisCell& c, float p, std::size_t nl, std::size_t np, std::size_t nr, Covered&& covered) {
        const bool at_lower = !(p > c.lo), at_upper = !(p < c.hi);
        // A plane on the cell's own face makes progress only by cutting off the triangles in it.
        if ((at_lower || at_upper) && np == 0) return;
        const float ct = rules_.traversal_cost, ci = rules_.intersection_cost;
        const float pl = (p - c.lo) * c.a + c.b, pr = (c.hi - p) * c.a + c.b;
        auto cost_of = [&](std::size_t a, std::size_t b) {
            const float cost = ct + ci * (pl * float(a) + pr * float(b));
            return (a == 0 || b == 0) ? cost * kEmptySideBonus : cost;
        };
        if (!at_upper) {  // planar triangles to the left
            const float cost = cost_of(nl + np, nr);
            if (cost < best_sah_.cost) best_sah_ = SplitChoice{c.axis, p, true, cost, Rule::sah};
        }
        if (!at_lower) {  // planar triangles to the right
            const float cost = cost_of(nl, nr + np);
            if (cost < best_sah_.cost) best_sah_ = SplitChoice{c.axis, p, false, cost, Rule::sah};
        }
        consider_empty_side(c, p, nl, nr);
        if (np > 0 && rules_.flat_cell_rule && c.cross_section > 0.0 && covered()) {
            const bool to_left = at_lower || (!at_upper && p - c.lo <= c.hi - p);
            const float cost = to_left ? cost_of(nl + np, nr) : cost_of(nl, nr + np);
            if (cost < best_flat_.cost) best_flat_ = SplitChoice{c.axis, p, to_left, cost, Rule::flat_cell};
        }
    }

    // Rule 1's part of consider(): a plane inside the cell with nothing below it (nl == 0) or
    // nothing above it (nr == 0); the triangles lying in it go to the other side.
    void consider_empty_side(const AxisCell& c, float p, std::size_t nl, std::size_t nr) {
        if (!(p > c.lo) || !(p < c.hi)) return;
        const float left_empty = (p - c.lo) / (c.hi - c.lo), right_empty = (c.hi - p) / (c.hi - c.lo);
        if (nl == 0 && left_empty > best_empty_fraction_) {
            best_empty_fraction_ = left_empty;
            best_empty_ = SplitChoice{c.axis, p, false, 0.0f, Rule::empty_cell};
        }
        if (nr == 0 && right_empty > best_empty_fraction_) {
            best_empty_fraction_ = right_empty;
            best_empty_ = SplitChoice{c.axis, p, true, 0.0f, Rule::empty_cell};
        }
    }

    // The empty cell rule 1 takes among the planes seen, or no split (axis -1).
    SplitChoice empty_cell_choice() const {
        if (rules_.empty_cell_rule && best_empty_.axis >= 0 &&
            best_empty_fraction_ >= rules_.empty_cell_min_volume_fraction)
            return best_empty_;
        return SplitChoice{};
    }

    // Rule 1 (an empty cell large enough), else rule 2 (a covered plane, the cheapest), else the
    // cheapest plane if it costs less than testing the n triangles; no split (axis -1) otherwise.
    SplitChoice choice(std::size_t n) const {
        if (const SplitChoice empty = empty_cell_choice(); empty.axis >= 0) return empty;
        if (best_flat_.axis >= 0) return best_flat_;
        if (best_sah_.axis >= 0 && best_sah_.cost < rules_.intersection_cost * float(n)) return best_sah_;
        return SplitChoice{};
    }

private:
    const KdBuildRules& rules_;
    SplitChoice best_sah_, best_flat_, best_empty_;
    float best_empty_fraction_ = 0.0f;
};

// Rule 1 before any sweep. A sweep finds one side empty only at the triangles' tight bounds along
// an axis (the lowest lower side of their boxes: nothing below; the highest upper side: nothing
// above), so the empty cell rule 1 takes, which comes before every other choice, is known from the
// cell and the triangles' tight box alone: the same plane the whole sweep would return. No split
// (axis -1) when rule 1 takes none.
inline SplitChoice empty_cell_cut(const KdBuildRules& rules, const Box& cell, const Box& tight) {
    if (!rules.empty_cell_rule) return SplitChoice{};
    SplitSearch search(rules);
    const float area = cell.surface_area();
    for (int k = 0; k < 3; ++k) {
        const AxisCell c(cell, k, area);
        if (!c.splittable()) continue;
        const float low = tight.lower[k], high = tight.upper[k];
        // As the sweep meets them: the lowest position first (nothing above it too if every
        // triangle lies in that one plane), then the highest.
        search.consider_empty_side(c, low, 0, high > low ? 1 : 0);
        if (high > low) search.consider_empty_side(c, high, 1, 0);
    }
    return search.empty_cell_choice();
}

}  // namespace beamtrace::kd
