#pragma once
// The storage of a DirectionSet and its constant-time nearest-direction lookup (inline: it runs
// once per ray).
//
// The lookup table covers the upper hemisphere through the octahedral map
//     (x, y, z), z >= 0  ->  (u, v) = (x, y) / (|x| + |y| + z),   |u| + |v| <= 1,
// cut into T x T square cells over [-1, 1]^2. A direction with z < 0 is looked up as its opposite
// (a direction stands for a line). Each cell lists the K directions that can be nearest to some
// direction inside it (a conservative bound, see direction_set.cpp), padded to K (even) by
// repeating the first, two 16-bit indices to a 32-bit word; a query compares exactly those K,
// never the whole set.
#include <cmath>
#include <cstdint>
#include <vector>

#include "beamtrace/vlf.hpp"

namespace beamtrace {

struct DirectionSet::Impl {
    int m = 0;      // grid steps per half side of the equal-area map (count = 2 m^2 + 1)
    int count = 0;  // l
    std::vector<Float3> dirs;
    std::vector<float> dx, dy, dz;  // the same, structure of arrays (SIMD gathers)

    int table = 0;         // T: cells per side of the lookup table
    int per_cell = 0;      // K: candidates per cell (even)
    float half_table = 0;  // T / 2
    // T * T * K / 2 words; candidate k of cell (iu, iv) is half k % 2 (low first) of word
    // (iv * T + iu) * K / 2 + k / 2.
    std::vector<std::uint32_t> candidate_pairs;

    // Cell of a (non-zero) direction: its octahedral coordinates after turning it into the upper
    // hemisphere, clamped into the table (rounding may put |u| a hair above 1).
    std::uint32_t cell(float x, float y, float z) const {
        const float s = std::fabs(x) + std::fabs(y) + std::fabs(z);
        const float inv = (z < 0.0f ? -1.0f : 1.0f) / s;
        int iu = int((x * inv + 1.0f) * half_table);
        int iv = int((y * inv + 1.0f) * half_table);
        iu = iu < 0 ? 0 : (iu >= table ? table - 1 : iu);
        iv = iv < 0 ? 0 : (iv >= table ? table - 1 : iv);
        return std::uint32_t(iv * table + iu);
    }

    Nearest nearest(float x, float y, float z) const {
        const std::uint32_t* c = candidate_pairs.data() + std::size_t(cell(x, y, z)) * std::size_t(per_cell / 2);
        std::uint32_t best = c[0] & 0xFFFFu;
        float best_dot = x * dx[best] + y * dy[best] + z * dz[best];
        for (int k = 1; k < per_cell; ++k) {
            const std::uint32_t i = (c[k / 2] >> (16 * (k & 1))) & 0xFFFFu;
            const float d = x * dx[i] + y * dy[i] + z * dz[i];
            if (std::fabs(d) > std::fabs(best_dot)) {
                best = i;
                best_dot = d;
            }
        }
        return Nearest{best, best_dot < 0.0f};
    }
};

}  // namespace beamtrace
