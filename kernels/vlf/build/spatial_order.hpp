#pragma once
// The order in which a field stores its triangles: along a Morton (Z-order) curve of their
// centroids over the field's box, so that triangles near one another in space lie near one another
// in memory. A tile's entries, and the triangles of neighbouring tiles, then share cache lines;
// meshes often list their faces in an order unrelated to space (the bunny's neighbouring faces lie
// some 16,000 places apart in the file). Inside the field a triangle is known by its place in this
// order; the API speaks the caller's ids, mapped at the edge (visibility_field.cpp, field_query.hpp,
// dynamic_update.cpp). Ties in a closest hit go to the smaller caller's id, so answers do not
// depend on this order.
#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "beamtrace/scene.hpp"

namespace beamtrace::vlf {

// order[k] = the caller's id of the triangle stored k-th (ties in the curve keep the caller's order).
inline std::vector<std::uint32_t> spatial_order(std::span<const Triangle> triangles, const Box& box) {
    auto spread = [](std::uint64_t v) {  // 21 bits -> every third bit of 63
        v &= 0x1FFFFF;
        v = (v | v << 32) & 0x1F00000000FFFFull;
        v = (v | v << 16) & 0x1F0000FF0000FFull;
        v = (v | v << 8) & 0x100F00F00F00F00Full;
        v = (v | v << 4) & 0x10C30C30C30C30C3ull;
        v = (v | v << 2) & 0x1249249249249249ull;
        return v;
    };
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const Triangle& t = triangles[i];
        std::uint64_t key = 0;
        for (int k = 0; k < 3; ++k) {
            const double c = (double(t.v0[k]) + t.v1[k] + t.v2[k]) / 3.0;
            const double extent = double(box.upper[k]) - box.lower[k];
            double q = extent > 0.0 ? (c - box.lower[k]) / extent * 2097152.0 : 0.0;
            q = q > 0.0 ? (q < 2097151.0 ? q : 2097151.0) : 0.0;  // clamped (a NaN goes to 0)
            key |= spread(std::uint64_t(q)) << k;
        }
        keys[i] = {key, std::uint32_t(i)};
    }
    std::stable_sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::uint32_t> order(triangles.size());
    for (std::size_t k = 0; k < keys.size(); ++k) order[k] = keys[k].second;
    return order;
}

}  // namespace beamtrace::vlf
