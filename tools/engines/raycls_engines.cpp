// raycls: the library's RayClassification (ray_classification.hpp) on the active rays side by side:
// Arvo and Kirk's 5D ray space made lazily, light buffers for rays sharing an end point (shadow rays
// towards a point light) or a start point (camera rays). Every timed pass starts with no cells, so
// the lazy build is inside the time; the counted pass (stats) does too, and two passes after it keep
// its cells (stats warm_trace_seconds, warm_mrays_per_s: the query term alone).

#include <algorithm>
#include <chrono>

#include "beamtrace/ray_classification.hpp"
#include "engines/active_rays.hpp"
#include "engines/engine_registry.hpp"

namespace beamtrace::workload {
namespace {

class RayClsEngine : public Engine {
public:
    std::string name() const override { return "raycls"; }
    void build(const Scene& scene, const EngineOptions& options) override {
        prepared_.forget();
        tree_ = std::make_unique<KdTree>(KdTree::build(scene, options.kd_rules, options.build_progress));
        raycls_ = std::make_unique<RayClassification>(*tree_, options.raycls);
    }
    double build_seconds() const override { return tree_->stats().build_seconds; }
    std::size_t memory_bytes() const override { return tree_->stats().bytes + raycls_->stats().memory_peak_bytes; }

    void prepare(const RaySet& rays) override { prepared_.prepare(rays); }

    // The cells are freed before the clock starts: the pass makes the ones it needs.
    double timed_pass(const RaySet& rays, EngineAnswers& answers, int threads, int variant) override {
        raycls_->clear();
        threads_ = threads;
        return Engine::timed_pass(rays, answers, threads, variant);
    }

    void trace(const RaySet& rays, bool closest, EngineAnswers& a, int threads) const override {
        prepared_.answer(*raycls_, rays, closest, a, QueryOptions{threads, nullptr});
    }

    nlohmann::json stats(const RaySet& rays) const override {
        QueryCounters c;
        EngineAnswers a;
        const ActiveRays in = active_rays(rays);
        raycls_->clear();
        answer_rays(*raycls_, in, closest_hit(rays.mode), a, QueryOptions{1, &c});
        const RayClsStats s = raycls_->stats();
        // Warm: the same rays again with the cells the pass above made (a renderer's next frame with
        // the same light), on the timed passes' threads, best of two; not the engine's speed, which
        // pays for its cells every pass.
        double warm = kInfinity;
        for (int pass = 0; pass < 2; ++pass) {
            EngineAnswers again;
            const auto start = std::chrono::steady_clock::now();
            answer_rays(*raycls_, in, closest_hit(rays.mode), again, QueryOptions{threads_, nullptr});
            warm = std::min(warm, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        }
        const auto& r = c.raycls;
        const double n = r.rays ? double(r.rays) : 1.0;
        const RayClsSettings& set = raycls_->settings();
        nlohmann::json j = {{"cells_created", s.cells_created},
                            {"cells_freed", s.cells_freed},
                            {"candidate_entries", s.candidate_entries},
                            {"memory_bytes", s.memory_bytes},
                            {"memory_peak_bytes", s.memory_peak_bytes},
                            {"light_buffers", s.light_buffers},
                            {"light_buffer_ray_fraction", double(r.light_buffer_rays) / n},
                            {"run_ray_fraction", double(r.run_rays) / n},
                            {"cache_hit_rate", double(r.cache_hits) / n},
                            {"descent_steps_per_ray", double(r.descent_steps) / n},
                            {"candidates_per_ray", double(r.candidates) / n},
                            {"triangle_tests_per_ray", double(c.triangle_tests) / n},
                            {"kd_fallback_rays", c.rays},
                            {"lazy_build_seconds", s.lazy_build_seconds},
                            {"warm_trace_seconds", warm},
                            {"warm_mrays_per_s", warm > 0.0 ? double(in.rays.size()) * 1e-6 / warm : 0.0},
                            {"warm_threads", threads_},
                            {"max_depth_reached", s.max_depth_reached},
                            {"growth_stops", s.growth_stops},
                            {"settings",
                             {{"max_depth", set.max_depth},
                              {"light_buffer_max_depth", set.light_buffer_max_depth},
                              {"min_candidates", set.min_candidates},
                              {"rays_per_new_cell", set.rays_per_new_cell},
                              {"entries_per_ray", set.entries_per_ray},
                              {"cache", set.cache},
                              {"light_buffers", set.light_buffers},
                              {"packet_light_buffers", set.packet_light_buffers},
                              {"memory_budget_bytes", set.memory_budget_bytes}}}};
        j.update(tree_json(tree_->stats()));
        return j;
    }

private:
    std::unique_ptr<KdTree> tree_;
    std::unique_ptr<RayClassification> raycls_;
    PreparedRays prepared_;
    int threads_ = 1;  // of the last timed pass (the warm passes in stats() use as many)
};

}  // namespace

std::unique_ptr<Engine> make_raycls_engine() { return std::make_unique<RayClsEngine>(); }

}  // namespace beamtrace::workload
