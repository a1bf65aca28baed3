#include "crsh/ray_hierarchy.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "common/ray_validity.hpp"
#include "crsh/radix_sort.hpp"

namespace beamtrace::crsh {

namespace {

using Clock = std::chrono::steady_clock;

std::uint64_t nanoseconds_since(Clock::time_point start) {
    return static_cast<std::uint64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - start).count());
}

// f(begin, end) over [0, n), in parallel or not.
template <class F>
void for_range(std::size_t n, bool parallel, std::size_t grain, F&& f) {
    if (!parallel || n <= grain) {
        f(std::size_t{0}, n);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                      [&](const tbb::blocked_range<std::size_t>& r) { f(r.begin(), r.end()); });
}

constexpr double kPad = 1.0 + 1e-14;  // covers the double rounding of a distance

}  // namespace

RayNode leaf_node(std::span<const BoundingRay> rays) {
    RayNode node;
    Vec3d lo = rays.front().start, hi = lo;
    for (const BoundingRay& b : rays) {
        lo = Vec3d(std::min(lo.x, b.start.x), std::min(lo.y, b.start.y), std::min(lo.z, b.start.z));
        hi = Vec3d(std::max(hi.x, b.start.x), std::max(hi.y, b.start.y), std::max(hi.z, b.start.z));
    }
    node.centre = (lo + hi) * 0.5;
    node.length = 0.0;
    for (const BoundingRay& b : rays) {
        node.radius = std::max(node.radius, length(b.start - node.centre) * kPad);
        node.length = std::max(node.length, b.length);
    }
    std::array<Vec3d, 64> dirs;
    const std::size_t n = std::min<std::size_t>(rays.size(), dirs.size());
    for (std::size_t i = 0; i < n; ++i) dirs[i] = rays[i].dir;
    const std::span<const Vec3d> d(dirs.data(), n);
    node.cone = grow_cone(d);
    if (node.cone.spread < kPi) node.cone.spread = std::min(node.cone.spread, largest_angle(node.cone.axis, d));
    finish_node(node);
    return node;
}

RayNode merged_node(std::span<const RayNode> children) {
    RayNode node;
    Vec3d sum{0, 0, 0};
    for (const RayNode& c : children) sum = sum + c.centre;
    node.centre = sum * (1.0 / static_cast<double>(children.size()));
    std::array<Cone, 64> cones;
    const std::size_t n = std::min<std::size_t>(children.size(), cones.size());
    node.length = 0.0;
    for (std::size_t i = 0; i < children.size(); ++i) {
        const RayNode& c = children[i];
        node.radius = std::max(node.radius, (length(c.centre - node.centre) + c.radius) * kPad);
        node.length = std::max(node.length, c.length);  // the radius already reaches every child's starts
        if (i < n) cones[i] = c.cone;
    }
    node.cone = merge_cones(std::span<const Cone>(cones.data(), n));
    finish_node(node);
    return node;
}

RayHierarchy build_ray_hierarchy(std::span<const Ray> rays, const CrshSettings& settings, const Box& scene_box,
                                 bool parallel, QueryCounters* counters) {
    Clock::time_point start = Clock::now();
    RayHierarchy h;
    h.order.reserve(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (describes_segment(rays[i])) h.order.push_back(static_cast<std::uint32_t>(i));
    const std::size_t n = h.order.size();

    // Bounding rays (in input order of the valid rays) and keys.
    std::vector<BoundingRay> bounds(n);
    std::vector<std::uint64_t> keys(settings.sort ? n : 0);
    const PositionCode position(scene_box, settings.key_position_bits);
    for_range(n, parallel, 4096, [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
            bounds[k] = bounding_ray(rays[h.order[k]], settings.key);
            if (settings.sort) keys[k] = ray_key(bounds[k], position);
        }
    });
    if (counters) {
        counters->crsh.rays += n;
        counters->crsh.key_ns += nanoseconds_since(start);
        start = Clock::now();
    }

    // Sort positions 0..n-1 by key; `slot` maps a sorted position to its bounding ray.
    std::vector<std::uint32_t> slot;
    if (settings.sort) {
        slot.resize(n);
        for (std::size_t k = 0; k < n; ++k) slot[k] = static_cast<std::uint32_t>(k);
        radix_sort(keys, slot);
        std::vector<std::uint32_t> sorted(n);
        for (std::size_t k = 0; k < n; ++k) sorted[k] = h.order[slot[k]];
        h.order.swap(sorted);
    }
    if (counters) {
        counters->crsh.sort_ns += nanoseconds_since(start);
        start = Clock::now();
    }

    // Level 1, then each level above.
    const std::size_t f = static_cast<std::size_t>(settings.fanout);
    h.levels.resize(static_cast<std::size_t>(settings.levels));
    std::vector<RayNode>& leaves = h.levels[0];
    leaves.resize((n + f - 1) / f);
    for_range(leaves.size(), parallel, 256, [&](std::size_t b, std::size_t e) {
        std::array<BoundingRay, 64> group;
        for (std::size_t j = b; j < e; ++j) {
            const std::size_t first = j * f, count = std::min(f, n - first);
            for (std::size_t i = 0; i < count; ++i) group[i] = bounds[settings.sort ? slot[first + i] : first + i];
            leaves[j] = leaf_node(std::span<const BoundingRay>(group.data(), count));
            if (!settings.segment_bound) leaves[j].length = std::numeric_limits<double>::infinity();
            leaves[j].first = static_cast<std::uint32_t>(first);
            leaves[j].count = static_cast<std::uint32_t>(count);
        }
    });
    for (std::size_t l = 1; l < h.levels.size(); ++l) {
        const std::vector<RayNode>& below = h.levels[l - 1];
        std::vector<RayNode>& level = h.levels[l];
        level.resize((below.size() + f - 1) / f);
        for (std::size_t j = 0; j < level.size(); ++j) {
            const std::size_t first = j * f, count = std::min(f, below.size() - first);
            level[j] = merged_node(std::span<const RayNode>(below.data() + first, count));
            level[j].first = static_cast<std::uint32_t>(first);
            level[j].count = static_cast<std::uint32_t>(count);
        }
    }
    if (counters) {
        for (std::size_t l = 0; l < h.levels.size(); ++l) counters->crsh.nodes[l] += h.levels[l].size();
        counters->crsh.hierarchy_ns += nanoseconds_since(start);
    }
    return h;
}

}  // namespace beamtrace::crsh
