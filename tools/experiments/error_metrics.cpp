#include "experiments/error_metrics.hpp"

#include <algorithm>
#include <cmath>

#include "beamtrace/error.hpp"
#include "rays/ray_set.hpp"

namespace beamtrace::workload {

RelativeTError relative_t_error(const std::vector<Hit>& ours, const std::vector<Hit>& oracle) {
    if (ours.size() != oracle.size())
        throw Error("relative_t_error: " + std::to_string(ours.size()) + " hits against " +
                    std::to_string(oracle.size()) + " of the oracle");
    RelativeTError e;
    double sum = 0.0;
    for (std::size_t i = 0; i < ours.size(); ++i) {
        if (!ours[i].hit() || !oracle[i].hit() || !(oracle[i].t > 0.0f)) continue;
        const double reference = oracle[i].t;
        const double error = std::fabs(double(ours[i].t) - reference) / reference;
        if (std::isnan(error)) continue;
        sum += error;
        e.max = std::max(e.max, error);
        ++e.rays;
    }
    if (e.rays > 0) e.mean = sum / double(e.rays);
    return e;
}

double occlusion_fraction_mae(const std::vector<std::uint32_t>& pixel, const std::vector<std::uint8_t>& ours,
                              const std::vector<std::uint8_t>& oracle) {
    if (ours.size() != pixel.size() || oracle.size() != pixel.size())
        throw Error("occlusion_fraction_mae: " + std::to_string(pixel.size()) + " slots, " +
                    std::to_string(ours.size()) + " answers and " + std::to_string(oracle.size()) + " of the oracle");
    struct Counts {
        std::uint32_t rays = 0, ours = 0, oracle = 0;
    };
    std::uint32_t last = 0;
    bool any = false;
    for (std::uint32_t p : pixel)
        if (p != kNoPixel) last = std::max(last, p), any = true;
    if (!any) return 0.0;
    std::vector<Counts> pixels(std::size_t(last) + 1);
    for (std::size_t slot = 0; slot < pixel.size(); ++slot) {
        if (pixel[slot] == kNoPixel) continue;
        Counts& c = pixels[pixel[slot]];
        ++c.rays;
        c.ours += ours[slot] != 0;
        c.oracle += oracle[slot] != 0;
    }
    double sum = 0.0;
    std::size_t counted = 0;
    for (const Counts& c : pixels) {
        if (c.rays == 0) continue;
        sum += std::fabs(double(c.ours) - double(c.oracle)) / double(c.rays);
        ++counted;
    }
    return sum / double(counted);
}

}  // namespace beamtrace::workload
