#pragma once
// How far an engine's answers are from the oracle's, beyond the agree/ties/grazing/mismatch counts:
// the relative error of hit distances, and for ambient occlusion the error of each pixel's
// occlusion fraction (what a renderer would actually show).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "beamtrace/ray.hpp"

namespace beamtrace::workload {

// |t - t_oracle| / t_oracle over the rays where both sides hit (any triangle) and t_oracle > 0.
// Rays where only one side hits are not counted here (they are mismatches or grazing cases).
struct RelativeTError {
    std::uint64_t rays = 0;  // rays counted
    double mean = 0.0;       // 0 when no ray was counted
    double max = 0.0;
};

// ours and oracle are per slot and of the same size (throws beamtrace::Error otherwise).
RelativeTError relative_t_error(const std::vector<Hit>& ours, const std::vector<Hit>& oracle);

// Mean over pixels of |f - f_oracle|, where f is the fraction of a pixel's occlusion rays that are
// occluded. pixel[slot] is the slot's pixel (kNoPixel for inactive slots, which are ignored); ours
// and oracle are per slot (1 = occluded). Pixels without rays do not count; 0 when there are none.
// Throws beamtrace::Error if the sizes differ.
double occlusion_fraction_mae(const std::vector<std::uint32_t>& pixel, const std::vector<std::uint8_t>& ours,
                              const std::vector<std::uint8_t>& oracle);

}  // namespace beamtrace::workload
