#pragma once
// Inverse frustum culling (MLRTA section 3.3): the cell's planes separate it from the beam, using
// only the beam's rectangle on a plane (condition (3)) and its direction signs.
#include <cstdint>

#include "mlrta/beam.hpp"
#include "mlrta/split_rectangle.hpp"

namespace beamtrace::mlrta {

enum ChildMask : std::uint8_t { kNoChild = 0, kLower = 1, kUpper = 2, kBothChildren = 3 };

// Which children of a cell (box `cell`, split x_k = split) a coherent beam may enter (Figure 3 c-d):
// - start points all on one side and directions moving away from the plane: that side only;
// - the beam's rectangle on the split plane lies beyond the cell's face on another axis j: if the
//   rays move further out along j, the child beyond the plane (in the direction of travel) is
//   missed; if they move in, the child before the plane is missed.
inline ChildMask cull_split(const Beam& beam, const Box& cell, int k, float split) {
    const int sk = beam.sign[k];
    if (sk < 0 && beam.starts.upper[k] < split) return kLower;
    if (sk > 0 && beam.starts.lower[k] > split) return kUpper;
    bool near_possible = true, far_possible = true;
    // Every ray ends before it reaches the plane: the far side is out of reach (not in the paper's
    // figure; the leaf test (2) makes the same use of the segments' lengths).
    if (beam.plane_t(k, split).lo > beam.length.hi) far_possible = false;
    // The rectangle [lo_j, hi_j, lo_l, hi_l] against the cell's faces: lanes 0 and 2 beyond the
    // upper faces, lanes 1 and 3 before the lower ones (4-wide SSE).
    const int j = rectangle_axis(k, 0), l = rectangle_axis(k, 1);
    const __m128 rect = split_rectangle(beam, k, split);
    const __m128 faces = _mm_setr_ps(cell.upper[j], cell.lower[j], cell.upper[l], cell.lower[l]);
    const int outside = _mm_movemask_ps(
        _mm_or_ps(_mm_and_ps(_mm_cmpgt_ps(rect, faces), _mm_castsi128_ps(_mm_setr_epi32(-1, 0, -1, 0))),
                  _mm_and_ps(_mm_cmplt_ps(rect, faces), _mm_castsi128_ps(_mm_setr_epi32(0, -1, 0, -1)))));
    const int axes[2] = {j, l};
    for (int pair = 0; pair < 2; ++pair) {
        const int a = axes[pair];
        if ((outside >> (2 * pair + 1)) & 1) (beam.sign[a] < 0 ? far_possible : near_possible) = false;  // r.hi < lower
        if ((outside >> (2 * pair)) & 1) (beam.sign[a] > 0 ? far_possible : near_possible) = false;      // r.lo > upper
    }
    const ChildMask near = sk > 0 ? kLower : kUpper, far = sk > 0 ? kUpper : kLower;
    return ChildMask((near_possible ? near : 0) | (far_possible ? far : 0));
}

// The leaf test (2): with entry and exit parameter ranges of the three slabs of the box,
//   (min of j-entries) > (max of i-exits) for some pair of axes  =>  no ray meets the box;
// also when every ray ends before entering a slab or starts after leaving one.
inline bool beam_misses_box(const Beam& beam, const Box& box) {
    Interval entry[3], exit[3];
    for (int k = 0; k < 3; ++k) {
        const float in = beam.sign[k] > 0 ? box.lower[k] : box.upper[k];
        const float out = beam.sign[k] > 0 ? box.upper[k] : box.lower[k];
        entry[k] = beam.plane_t(k, in);
        exit[k] = beam.plane_t(k, out);
        if (exit[k].hi < 0.0f || entry[k].lo > beam.length.hi) return true;
    }
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            if (a != b && entry[a].lo > exit[b].hi) return true;
    return false;
}

}  // namespace beamtrace::mlrta
