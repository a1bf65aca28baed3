#include "kdtree/reference_bins.hpp"

namespace beamtrace::kd {

ReferenceBins::ReferenceBins(const Box& cell, const Box& tight, int bins) : bins_(bins) {
    float scale[3];
    for (int k = 0; k < 3; ++k) {
        lo_[k] = cell.lower[k];
        hi_[k] = cell.upper[k];
        lowest_[k] = tight.lower[k];
        highest_[k] = tight.upper[k];
        const bool binned = hi_[k] > lo_[k];
        binned_axes_ |= int(binned) << k;
        scale[k] = binned ? float(bins) / (hi_[k] - lo_[k]) : 0.0f;
    }
    lo4_ = _mm_setr_ps(lo_[0], lo_[1], lo_[2], 0.0f);
    scale4_ = _mm_setr_ps(scale[0], scale[1], scale[2], 0.0f);
    last_bin4_ = _mm_set1_epi32(bins - 1);
}

void ReferenceBins::add_planar(const CellReference& r, int axes) {
    for (int k = 0; k < 3; ++k) {
        if (!((axes >> k) & 1)) continue;
        const float p = r.box.lower[k];
        for (InPlane* in : {p == lowest_[k] ? &at_lowest_[std::size_t(k)] : nullptr,
                            p == highest_[k] ? &at_highest_[std::size_t(k)] : nullptr})
            if (in) {
                ++in->count;
                in->area += double(r.area);
            }
    }
}

}  // namespace beamtrace::kd
