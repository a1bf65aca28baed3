#include <cmath>
#include <string>

#include "beamtrace/error.hpp"
#include "beamtrace/kdtree.hpp"

namespace beamtrace {

void KdBuildRules::validate() const {
    auto fail = [](const std::string& what) { throw Error("kd-tree build rules: " + what); };
    if (!(traversal_cost > 0.0f) || !std::isfinite(traversal_cost)) fail("traversal_cost must be positive and finite");
    if (!(intersection_cost > 0.0f) || !std::isfinite(intersection_cost))
        fail("intersection_cost must be positive and finite");
    if (!(empty_cell_min_volume_fraction > 0.0f && empty_cell_min_volume_fraction <= 1.0f))
        fail("empty_cell_min_volume_fraction must be in (0, 1]");
    if (!(tiny_cell_min_area_fraction >= 0.0f && tiny_cell_min_area_fraction < 1.0f))
        fail("tiny_cell_min_area_fraction must be in [0, 1)");
    if (max_depth < 0 || max_depth > 60) fail("max_depth must be in [0, 60] (0 = automatic)");
    if (leaf_triangles < 0) fail("leaf_triangles must not be negative");
    if (binned_above < 0) fail("binned_above must not be negative (0 = exact sweep everywhere)");
    if (bins < 2 || bins > kMaxBins)
        fail("bins must be in [2, " + std::to_string(kMaxBins) + "], not " + std::to_string(bins));
}

}  // namespace beamtrace
