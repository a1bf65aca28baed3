// O(N log N) SAH kd-tree build (Wald & Havran 2006: events sorted once, split lists kept sorted,
// straddling triangles clipped into both children) with the construction rules of MLRTA section 3.1:
//   rule 1: cut off an empty cell of at least `empty_cell_min_volume_fraction` of the parent volume;
//   rule 2: take a split plane completely covered by coplanar triangles, which go to the smaller side;
//   rule 3: make a leaf instead of splitting cells whose area is tiny relative to the scene's box.
// With KdBuildRules::binned_above the upper levels choose among bin boundaries instead
// (binned_builder.hpp) and hand the smaller cells to the exact sweep (event_sweep_builder.hpp).
#include <chrono>
#include <string>

#include "beamtrace/error.hpp"
#include "kdtree/binned_builder.hpp"

namespace beamtrace {
namespace kd {
namespace {

void build_tree(const Scene& scene, const KdBuildRules& rules, const KdTree::Progress& progress, KdTree::Impl& out) {
    const std::size_t count = scene.triangle_count();
    if (count > SplitEvent::kMaxTriangle)
        throw Error("kd-tree: " + std::to_string(count) + " triangles exceed the tree's limit of 2^30");
    BuildContext context(scene, rules, progress, out);
    CellReferences refs;
    refs.list.reserve(count);
    for (std::uint32_t t = 0; t < count; ++t) {
        if (scene.is_degenerate(t)) continue;
        const Triangle& tri = scene.triangle(t);
        const double area = 0.5 * length(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
        context.add_triangle(t, area);
        Box tb;
        tb.extend(tri.v0);
        tb.extend(tri.v1);
        tb.extend(tri.v2);
        refs.add(CellReference{tb, t, float(area)});
    }
    context.set_max_depth();
    EventSweepBuilder exact(context);
    BinnedBuilder(context, exact).build(out.bounds, refs, 0);
    context.finish_stats();

    out.gather_leaf_triangles();
    out.stats.bytes = out.nodes.size() * sizeof(KdNode) + out.triangle_ids.size() * sizeof(std::uint32_t) +
                      out.leaf_triangles.size() * sizeof(Triangle);
    if (progress) progress(1.0);
}

}  // namespace
}  // namespace kd

KdTree KdTree::build(const Scene& scene, const KdBuildRules& rules, const Progress& progress) {
    rules.validate();
    const auto start = std::chrono::steady_clock::now();
    auto impl = std::make_shared<Impl>(scene);
    impl->kernels = &triangle_kernels();
    kd::build_tree(scene, rules, progress, *impl);
    impl->stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return KdTree(std::move(impl));
}

const Scene& KdTree::scene() const { return impl_->scene; }
const KdBuildStats& KdTree::stats() const { return impl_->stats; }

}  // namespace beamtrace
