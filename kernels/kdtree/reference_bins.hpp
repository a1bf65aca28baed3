#pragma once
// The histograms of the binned SAH build (binned_builder.hpp): where a cell's triangle references
// start and end along each of its three axes, in equal bins, and how many lie in the planes of
// their tight bounds. One pass over the references, the three axes at once in SSE lanes.
#include <smmintrin.h>

#include <array>
#include <cstdint>
#include <vector>

#include "beamtrace/kdtree.hpp"
#include "beamtrace/scene.hpp"

namespace beamtrace::kd {

// A triangle in a cell: its id, the box of its part inside the cell (clipped_bounds) and the
// triangle's whole area (for rule 2's first test). 32 bytes.
struct CellReference {
    Box box;
    std::uint32_t tri;
    float area;
};
static_assert(sizeof(CellReference) == 32);

// A cell's references and the box around their boxes (their tight bounds, kept up as references
// are added, so that no pass is needed to know them).
struct CellReferences {
    std::vector<CellReference> list;
    Box bounds;

    void add(const CellReference& r) {
        list.push_back(r);
        bounds.extend(r.box);
    }
};

class ReferenceBins {
public:
    static constexpr int kMaxBins = KdBuildRules::kMaxBins;

    // `tight`: the box of the references' boxes. Axes along which the cell is flat are not binned.
    ReferenceBins(const Box& cell, const Box& tight, int bins);

    void add(const CellReference& r) {
        // Lanes x, y, z of both sides (the fourth lane, another field, lands in bin 0 unused).
        const __m128 lower = _mm_loadu_ps(&r.box.lower.x), upper = _mm_loadu_ps(&r.box.upper.x);
        alignas(16) std::int32_t first[4], last[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(first), bin_of(lower));
        _mm_store_si128(reinterpret_cast<__m128i*>(last), bin_of(upper));
        for (int k = 0; k < 3; ++k) {
            ++starts_[std::size_t(k)][std::size_t(first[k])];
            ++ends_[std::size_t(k)][std::size_t(last[k])];
        }
        const int planar = _mm_movemask_ps(_mm_cmpeq_ps(lower, upper)) & binned_axes_;
        if (planar) [[unlikely]]
            add_planar(r, planar);
    }

    int bins() const { return bins_; }
    // Position of boundary i (1..bins-1) of an axis, between bins i-1 and i.
    float boundary(int axis, int i) const {
        return std::min(lo_[axis] + (hi_[axis] - lo_[axis]) * (float(i) / float(bins_)), hi_[axis]);
    }
    // References whose lower (upper) side falls in a bin: starting (ending) there.
    std::uint32_t starts(int axis, int bin) const { return starts_[std::size_t(axis)][std::size_t(bin)]; }
    std::uint32_t ends(int axis, int bin) const { return ends_[std::size_t(axis)][std::size_t(bin)]; }

    // The references lying in the plane of the lowest lower side (highest upper side) along an
    // axis, and the sum of their triangles' whole areas.
    struct InPlane {
        std::size_t count = 0;
        double area = 0.0;
    };
    const InPlane& at_lowest(int axis) const { return at_lowest_[std::size_t(axis)]; }
    const InPlane& at_highest(int axis) const { return at_highest_[std::size_t(axis)]; }

private:
    __m128i bin_of(__m128 x) const {
        const __m128i b = _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(x, lo4_), scale4_));  // NaN or overflow: INT_MIN
        return _mm_min_epi32(_mm_max_epi32(b, _mm_setzero_si128()), last_bin4_);
    }
    void add_planar(const CellReference& r, int axes);

    int bins_;
    int binned_axes_ = 0;  // bit k: the cell is not flat along axis k
    float lo_[3], hi_[3], lowest_[3], highest_[3];
    __m128 lo4_, scale4_;
    __m128i last_bin4_;
    std::array<std::array<std::uint32_t, kMaxBins>, 3> starts_{}, ends_{};
    std::array<InPlane, 3> at_lowest_{}, at_highest_{};
};

}  // namespace beamtrace::kd
