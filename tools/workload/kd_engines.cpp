// kd1 (the kd-tree, one ray at a time) and brute (every triangle, the reference).
#include <chrono>

#include "beamtrace/error.hpp"
#include "workload/engine_registry.hpp"
#include "workload/single_ray_engine.hpp"

namespace beamtrace::workload {
namespace {

nlohmann::json counters_json(const TraversalCounters& c) {
    const double rays = c.rays ? double(c.rays) : 1.0;
    return {{"inner_steps_per_ray", double(c.inner_steps) / rays},
            {"leaves_per_ray", double(c.leaves) / rays},
            {"triangle_tests_per_ray", double(c.triangle_tests) / rays}};
}

class Kd1Engine : public SingleRayEngine {
public:
    std::string name() const override { return "kd1"; }
    void build(const Scene& scene, const EngineOptions& options) override {
        tree_ = std::make_unique<KdTree>(KdTree::build(scene, options.kd_rules, options.build_progress));
    }
    double build_seconds() const override { return tree_->stats().build_seconds; }
    std::size_t memory_bytes() const override { return tree_->stats().bytes; }

    nlohmann::json stats(const RaySet& rays) const override {
        const KdBuildStats& s = tree_->stats();
        TraversalCounters c;
        const bool closest = rays.mode == Mode::primary;
        for (std::size_t slot = 0; slot < rays.slots(); ++slot) {
            if (!rays.active(slot)) continue;
            if (closest) tree_->intersect(rays.ray(slot), c);
            else tree_->occluded(rays.ray(slot), c);
        }
        nlohmann::json j = counters_json(c);
        j["nodes"] = s.nodes;
        j["leaves"] = s.leaves;
        j["empty_leaves"] = s.empty_leaves;
        j["flat_leaves"] = s.flat_leaves;
        j["depth"] = s.depth;
        j["mean_triangles_per_leaf"] = s.mean_triangles_per_leaf;
        j["triangle_references"] = s.triangle_references;
        j["degenerate_triangles"] = s.degenerate_triangles;
        j["empty_cell_splits"] = s.empty_cell_splits;
        j["flat_cell_splits"] = s.flat_cell_splits;
        j["tiny_cell_leaves"] = s.tiny_cell_leaves;
        return j;
    }

protected:
    Hit intersect_one(const Ray& ray) const override { return tree_->intersect(ray); }
    bool occluded_one(const Ray& ray) const override { return tree_->occluded(ray); }

private:
    std::unique_ptr<KdTree> tree_;
};

class BruteEngine : public SingleRayEngine {
public:
    static constexpr std::size_t kMaxTriangles = 100000;
    std::string name() const override { return "brute"; }
    void build(const Scene& scene, const EngineOptions&) override {
        if (scene.triangle_count() > kMaxTriangles)
            throw Error("engine brute refuses scenes over 100,000 triangles (this one has " +
                        std::to_string(scene.triangle_count()) + "): it tests every triangle against every ray");
        scene_ = std::make_unique<Scene>(scene);
    }
    double build_seconds() const override { return 0.0; }
    std::size_t memory_bytes() const override { return 0; }
    nlohmann::json stats(const RaySet& rays) const override {
        return {{"triangle_tests_per_ray", double(scene_->triangle_count() - scene_->degenerate_count())},
                {"rays", rays.ray_count}};
    }

protected:
    Hit intersect_one(const Ray& ray) const override { return intersect_brute_force(*scene_, ray); }
    bool occluded_one(const Ray& ray) const override { return occluded_brute_force(*scene_, ray); }

private:
    std::unique_ptr<Scene> scene_;
};

}  // namespace

std::unique_ptr<Engine> make_kd1_engine() { return std::make_unique<Kd1Engine>(); }
std::unique_ptr<Engine> make_brute_engine() { return std::make_unique<BruteEngine>(); }

}  // namespace beamtrace::workload
