#pragma once
// A kd-tree over a Scene: SAH build with the construction rules of MLRTA (Reshetov et al. 2005,
// section 3.1), single-ray closest-hit and occlusion traversal.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"
#include "beamtrace/stats.hpp"

namespace beamtrace {

// How the tree is built. Defaults are documented in docs/kdtree.md.
struct KdBuildRules {
    // Surface-area-heuristic costs of one traversal step and of one triangle test.
    float traversal_cost = 1.0f;
    float intersection_cost = 1.5f;

    // MLRTA rule 1: always cut off an empty cell whose volume is at least this fraction of its parent.
    bool empty_cell_rule = true;
    float empty_cell_min_volume_fraction = 0.10f;

    // MLRTA rule 2: prefer a split plane completely covered by coplanar triangles; those triangles
    // go to the smaller sub-cell (which makes flat, "2D" cells).
    bool flat_cell_rule = true;

    // MLRTA rule 3: no cell whose surface area is below this fraction of the scene box's area.
    bool tiny_cell_rule = true;
    float tiny_cell_min_area_fraction = 1e-7f;

    // Hard limits: 0 = automatic depth (8 + 1.3 log2 N, at most 60).
    int max_depth = 0;
    // Cells with at most this many triangles become leaves without evaluating splits.
    int leaf_triangles = 1;

    // Throws beamtrace::Error if a constant is out of range (negative costs, fractions outside [0,1]).
    void validate() const;
};

// Counters of one traversal, gathered only by the counting variants (zero cost otherwise).
struct TraversalCounters {
    std::uint64_t rays = 0;
    std::uint64_t inner_steps = 0;     // inner nodes visited
    std::uint64_t leaves = 0;          // leaves visited
    std::uint64_t triangle_tests = 0;  // ray/triangle tests performed

    TraversalCounters& operator+=(const TraversalCounters& o) {
        rays += o.rays; inner_steps += o.inner_steps; leaves += o.leaves; triangle_tests += o.triangle_tests;
        return *this;
    }
};

class KdTree {
public:
    // progress (optional) is called with a fraction in [0,1] from the building thread.
    using Progress = std::function<void(double)>;
    static KdTree build(const Scene& scene, const KdBuildRules& rules = {}, const Progress& progress = {});

    // Closest hit within [ray.tnear, ray.tfar]; no hit if none.
    Hit intersect(const Ray& ray) const;
    // Any hit within [ray.tnear, ray.tfar].
    bool occluded(const Ray& ray) const;
    // Same, accumulating counters.
    Hit intersect(const Ray& ray, TraversalCounters& counters) const;
    bool occluded(const Ray& ray, TraversalCounters& counters) const;

    const Scene& scene() const;
    const KdBuildStats& stats() const;

    // Read-only view of the tree for other traversal algorithms in the library (beams, packets).
    struct Impl;
    const Impl& impl() const { return *impl_; }
    // A tree assembled by other means (tests build trees node by node to reach exact cases).
    static KdTree from_impl(std::shared_ptr<const Impl> impl) { return KdTree(std::move(impl)); }

private:
    explicit KdTree(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
    std::shared_ptr<const Impl> impl_;
};

// Brute force: every triangle against the ray. The reference the kd-tree is tested against.
Hit intersect_brute_force(const Scene& scene, const Ray& ray);
bool occluded_brute_force(const Scene& scene, const Ray& ray);

}  // namespace beamtrace
