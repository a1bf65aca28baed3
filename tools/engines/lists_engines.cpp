// lists (Fournier and Poulin's hierarchy of 1D sorted lists) and lists-flat (the same lists without
// the hierarchy: the paper's Table 1), the library's SortedLists (sorted_lists.hpp) on the active
// rays side by side. Both are exact baselines, not fast engines; like brute, they refuse scenes
// whose per-ray work would make a run pointless (lists-flat treats O(triangles) events per ray).
#include <string>

#include "beamtrace/error.hpp"
#include "engines/active_rays.hpp"
#include "engines/engine_registry.hpp"

namespace beamtrace::workload {
namespace {

class ListsEngine : public Engine {
public:
    // lists-flat: every ray walks every triangle's events (as brute tests every triangle); lists: the
    // per-ray state is 8 bytes per triangle per thread.
    static constexpr std::size_t kMaxFlatTriangles = 100000, kMaxTriangles = 20'000'000;

    explicit ListsEngine(bool flat) : flat_(flat) {}
    std::string name() const override { return flat_ ? "lists-flat" : "lists"; }

    void build(const Scene& scene, const EngineOptions& options) override {
        prepared_.forget();
        const std::size_t limit = flat_ ? kMaxFlatTriangles : kMaxTriangles;
        if (scene.triangle_count() > limit)
            throw Error(
                "engine " + name() + " refuses scenes over " + std::to_string(limit) + " triangles (this one has " +
                std::to_string(scene.triangle_count()) +
                (flat_ ? "): every ray walks the events of every triangle" : "): a baseline, not a fast engine"));
        SortedListRules rules = options.lists;
        rules.flat = flat_;
        lists_ = std::make_unique<SortedLists>(SortedLists::build(scene, rules));
    }
    double build_seconds() const override { return lists_->stats().build_seconds; }
    std::size_t memory_bytes() const override { return lists_->stats().memory_bytes; }

    void prepare(const RaySet& rays) override { prepared_.prepare(rays); }

    void trace(const RaySet& rays, bool closest, EngineAnswers& a, int threads) const override {
        prepared_.answer(*lists_, rays, closest, a, QueryOptions{threads, nullptr});
    }

    nlohmann::json stats(const RaySet& rays) const override {
        QueryCounters c;
        EngineAnswers a;
        const ActiveRays in = active_rays(rays);
        const bool closest = closest_hit(rays.mode);
        answer_rays(*lists_, in, closest, a, QueryOptions{1, &c});
        std::uint64_t hits = 0;
        if (closest)
            for (const Hit& h : a.ray_hits) hits += h.hit() ? 1 : 0;
        else
            for (std::uint8_t o : a.ray_occluded) hits += o ? 1 : 0;
        const double n = c.rays ? double(c.rays) : 1.0;
        const SortedListStats& s = lists_->stats();
        const SortedListRules& r = lists_->rules();
        // The fewest tests any method can make: one per ray that hits (the paper's "minimum").
        const double minimum = double(hits) / n;
        const double tests = double(c.triangle_tests) / n;
        return {{"rays", c.rays},
                {"box_tests_per_ray", double(c.triangle_tests + c.lists.volumes_opened) / n},
                {"triangle_tests_per_ray", tests},
                {"events_per_ray", double(c.lists.events) / n},
                {"walked_events_per_ray", double(c.lists.walked_events) / n},
                {"volumes_opened_per_ray", double(c.lists.volumes_opened) / n},
                {"heap_ops_per_ray", double(c.lists.heap_ops) / n},
                {"min_tests_per_ray", minimum},
                {"tests_over_minimum", minimum > 0 ? tests / minimum : 0.0},
                {"memory_bytes", s.memory_bytes},
                {"build_seconds", s.build_seconds},
                {"volumes", s.volumes},
                {"events", s.events},
                {"depth", s.depth},
                {"mean_children", s.mean_children},
                {"special_cells", s.special_cells},
                {"degenerate_triangles", s.degenerate_triangles},
                {"flat", r.flat},
                {"grid", {r.grid[0], r.grid[1], r.grid[2]}},
                {"leaf_objects", r.leaf_objects}};
    }

private:
    bool flat_;
    std::unique_ptr<SortedLists> lists_;
    PreparedRays prepared_;
};

}  // namespace

std::unique_ptr<Engine> make_lists_engine(bool flat) { return std::make_unique<ListsEngine>(flat); }

}  // namespace beamtrace::workload
