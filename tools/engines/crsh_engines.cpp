// crsh (Reis, Costa, Pereira 2017: rays hashed and radix-sorted, a two-level ray-space hierarchy,
// object bounding spheres first) and rah (Roger, Assarsson, Holzschuch 2007: the same hierarchy over
// the rays in input order, every triangle against every top node). Both are the library's Crsh
// (crsh.hpp) on the active rays side by side; shadow rays are keyed and bounded from the light end
// (CrshKey::end_point), every other mode from the origin. Neither has a geometry hierarchy, so both
// refuse ray sets whose predicted top-level work exceeds the budget (docs/crsh.md).
#include <cstdio>
#include <string>

#include "beamtrace/error.hpp"
#include "engines/active_rays.hpp"
#include "engines/engine_registry.hpp"

namespace beamtrace::workload {
namespace {

// A count as an integer, or in millions from a million on.
std::string count_text(std::uint64_t x) {
    if (x < 1'000'000) return std::to_string(x);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.1f million", double(x) / 1e6);
    return buf;
}

class CrshEngine : public Engine {
public:
    explicit CrshEngine(bool sort) : sort_(sort) {}
    std::string name() const override { return sort_ ? "crsh" : "rah"; }

    void build(const Scene& scene, const EngineOptions& options) override {
        prepared_.forget();
        CrshSettings s = options.crsh;
        s.sort = sort_;
        s.object_spheres = sort_;
        s.object_of_triangle = sort_ ? options.object_of_triangle : std::span<const std::uint32_t>{};
        crsh_ = std::make_unique<Crsh>(scene, s);
        budget_ = options.crsh_budget;
    }
    double build_seconds() const override { return crsh_->stats().build_seconds; }
    std::size_t memory_bytes() const override { return crsh_->stats().memory_bytes; }

    void prepare(const RaySet& rays) override {
        check_budget(rays.ray_count);
        prepared_.prepare(rays);
    }

    // Everything of the method is in the call: keys, sort, nodes, traversal, final tests.
    void trace(const RaySet& rays, bool closest, EngineAnswers& a, int threads) const override {
        check_budget(rays.ray_count);
        prepared_.answer(crsh_->with_key(key_for(rays)), rays, closest, a, QueryOptions{threads, nullptr});
    }

    nlohmann::json stats(const RaySet& rays) const override {
        QueryCounters c;
        EngineAnswers a;
        const ActiveRays in = active_rays(rays);
        const Crsh crsh = crsh_->with_key(key_for(rays));
        answer_rays(crsh, in, closest_hit(rays.mode), a, QueryOptions{1, &c});
        const QueryCounters::Crsh& k = c.crsh;
        const CrshStats& s = crsh_->stats();
        const CrshSettings& settings = crsh.settings();
        const std::uint64_t total = k.object_sphere_tests + k.sphere_cone_tests + k.triangle_tests;
        const double brute = double(k.rays) * double(s.triangles);
        const double n = k.rays ? double(k.rays) : 1.0;
        nlohmann::json levels = nlohmann::json::array();
        for (int l = 0; l < settings.levels; ++l)
            levels.push_back({{"level", l + 1},
                              {"nodes", k.nodes[l]},
                              {"sphere_cone_tests", k.level_tests[l]},
                              {"hits", k.level_hits[l]}});
        return {{"rays", k.rays},
                {"fanout", settings.fanout},
                {"levels", settings.levels},
                {"sort", settings.sort},
                {"object_spheres", settings.object_spheres},
                {"key", settings.key == CrshKey::end_point ? "end_point" : "origin"},
                {"key_position_bits", settings.key_position_bits},
                {"segment_bound", settings.segment_bound},
                {"objects", s.objects},
                {"largest_object", s.largest_object},
                {"degenerate_triangles", s.degenerate_triangles},
                {"top_nodes", k.nodes[settings.levels - 1]},
                {"level_stats", levels},
                {"object_sphere_tests", k.object_sphere_tests},
                {"object_sphere_hits", k.object_sphere_hits},
                {"sphere_cone_tests", k.sphere_cone_tests},
                {"triangle_tests", k.triangle_tests},
                {"total_tests", total},
                {"brute_force_tests", brute},
                {"tests_fraction_of_brute_force", brute > 0.0 ? double(total) / brute : 0.0},
                {"triangle_tests_per_ray", double(k.triangle_tests) / n},
                {"total_tests_per_ray", double(total) / n},
                {"predicted_top_level_tests", crsh_->predicted_top_level_tests(rays.ray_count)},
                {"budget", budget_},
                {"key_seconds", double(k.key_ns) * 1e-9},
                {"sort_seconds", double(k.sort_ns) * 1e-9},
                {"hierarchy_seconds", double(k.hierarchy_ns) * 1e-9},
                {"traversal_seconds", double(k.traversal_ns) * 1e-9}};
    }

private:
    static CrshKey key_for(const RaySet& rays) {
        return rays.mode == Mode::shadow ? CrshKey::end_point : CrshKey::origin;
    }

    void check_budget(std::size_t ray_count) const {
        const std::uint64_t predicted = crsh_->predicted_top_level_tests(ray_count);
        if (predicted <= budget_) return;
        const CrshStats& s = crsh_->stats();
        std::uint64_t top_nodes = ray_count;
        const std::uint64_t f = std::uint64_t(crsh_->settings().fanout);
        for (int l = 0; l < crsh_->settings().levels; ++l) top_nodes = (top_nodes + f - 1) / f;
        const std::string per_node = sort_ ? std::to_string(s.objects) + " object spheres + " +
                                                 std::to_string(s.largest_object) + " triangles of the largest object"
                                           : std::to_string(s.triangles - s.degenerate_triangles) + " triangles";
        throw Error("engine " + name() + " refuses this work: " + std::to_string(ray_count) + " rays make " +
                    std::to_string(top_nodes) + " top nodes x (" + per_node + ") = " + count_text(predicted) +
                    " predicted top-level sphere tests, over the budget of " + count_text(budget_) +
                    " (--crsh-budget; it has no geometry hierarchy: docs/crsh.md)");
    }

    bool sort_;
    std::unique_ptr<Crsh> crsh_;
    std::uint64_t budget_ = EngineOptions::kDefaultCrshBudget;
    PreparedRays prepared_;
};

}  // namespace

std::unique_ptr<Engine> make_crsh_engine(bool sort) { return std::make_unique<CrshEngine>(sort); }

}  // namespace beamtrace::workload
