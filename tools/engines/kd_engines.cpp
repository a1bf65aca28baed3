// kd1 (the kd-tree, one ray at a time), kd16 (4x4 packets by interval traversal from the root: the
// paper's "no MLRT") and brute (every triangle, the reference).
#include "beamtrace/error.hpp"
#include "engines/active_rays.hpp"
#include "engines/engine_registry.hpp"
#include "engines/parallel.hpp"

namespace beamtrace::workload {

std::unique_ptr<KdTree> build_packet_tree(const Scene& scene, const EngineOptions& options) {
    KdExperimental x;
    x.triangle_culling = options.mlrta.experimental.triangle_culling;
    auto tree = std::make_unique<KdTree>(KdTree::build(scene, options.kd_rules, options.build_progress).with_experimental(x));
    tree->prepare_packet_queries();
    return tree;
}

nlohmann::json tree_json(const KdBuildStats& s) {
    return {{"nodes", s.nodes},
            {"leaves", s.leaves},
            {"empty_leaves", s.empty_leaves},
            {"flat_leaves", s.flat_leaves},
            {"depth", s.depth},
            {"mean_triangles_per_leaf", s.mean_triangles_per_leaf},
            {"triangle_references", s.triangle_references},
            {"degenerate_triangles", s.degenerate_triangles},
            {"empty_cell_splits", s.empty_cell_splits},
            {"flat_cell_splits", s.flat_cell_splits},
            {"tiny_cell_leaves", s.tiny_cell_leaves},
            {"sah_cost", s.sah_cost},
            {"binned_splits", s.binned_splits}};
}

namespace {

class Kd1Engine : public Engine {
public:
    std::string name() const override { return "kd1"; }
    void build(const Scene& scene, const EngineOptions& options) override {
        prepared_.forget();
        tree_ = std::make_unique<KdTree>(KdTree::build(scene, options.kd_rules, options.build_progress));
    }
    double build_seconds() const override { return tree_->stats().build_seconds; }
    std::size_t memory_bytes() const override { return tree_->stats().bytes; }

    // The active rays side by side, made once per ray set outside the timed passes.
    void prepare(const RaySet& rays) override { prepared_.prepare(rays); }

    // The answers of the active rays (by ray, spread after the timed region).
    void trace(const RaySet& rays, bool closest, EngineAnswers& a, int threads) const override {
        prepared_.answer(*tree_, rays, closest, a, QueryOptions{threads, nullptr});
    }

    nlohmann::json stats(const RaySet& rays) const override {
        QueryCounters c;
        EngineAnswers a;
        const ActiveRays in = active_rays(rays);
        answer_rays(*tree_, in, closest_hit(rays.mode), a, QueryOptions{1, &c});
        const double n = c.rays ? double(c.rays) : 1.0;
        nlohmann::json j = {{"inner_steps_per_ray", double(c.inner_steps) / n},
                            {"leaves_per_ray", double(c.leaves) / n},
                            {"triangle_tests_per_ray", double(c.triangle_tests) / n}};
        j.update(tree_json(tree_->stats()));
        return j;
    }

private:
    std::unique_ptr<KdTree> tree_;
    PreparedRays prepared_;
};

class Kd16Engine : public Engine {
public:
    std::string name() const override { return "kd16"; }
    void build(const Scene& scene, const EngineOptions& options) override {
        tree_ = build_packet_tree(scene, options);
        settings_ = options.mlrta;
    }
    double build_seconds() const override { return tree_->stats().build_seconds; }
    std::size_t memory_bytes() const override { return tree_->stats().bytes + tree_->packet_table_bytes(); }

    void trace(const RaySet& rays, bool closest, EngineAnswers& a, int threads) const override {
        answer_packets(*tree_, rays, closest, a, QueryOptions{threads, nullptr});
    }

    nlohmann::json stats(const RaySet& rays) const override {
        QueryCounters c;
        EngineAnswers a;
        answer_packets(*tree_, rays, closest_hit(rays.mode), a, QueryOptions{1, &c});
        nlohmann::json j = packet_counters_json(c, tree_->stats().nodes, tree_->experimental().triangle_culling);
        j.update(mlrta_settings_json(settings_));  // the settings this engine was given (the JSON contract's keys)
        return j;
    }

private:
    std::unique_ptr<KdTree> tree_;
    MlrtaSettings settings_;
};

class BruteEngine : public Engine {
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

    // The reference of the tests: every triangle against every active ray (not an accelerator).
    void trace(const RaySet& rays, bool closest, EngineAnswers& a, int threads) const override {
        a.form = EngineAnswers::Form::slots;
        if (closest)
            a.hits.assign(rays.slots(), Hit{});
        else
            a.occluded.assign(rays.slots(), 0);
        for_packet_ranges(rays.packets.size(), threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t p = b; p < e; ++p)
                for (std::uint32_t m = rays.packets[p].active & 0xFFFFu; m; m &= m - 1) {
                    const int i = __builtin_ctz(m);
                    const Ray r = rays.packets[p].ray(i);
                    if (closest)
                        a.hits[p * 16 + std::size_t(i)] = intersect_brute_force(*scene_, r);
                    else
                        a.occluded[p * 16 + std::size_t(i)] = occluded_brute_force(*scene_, r);
                }
        });
    }
    nlohmann::json stats(const RaySet& rays) const override {
        return {{"triangle_tests_per_ray", double(scene_->triangle_count() - scene_->degenerate_count())},
                {"rays", rays.ray_count}};
    }

private:
    std::unique_ptr<Scene> scene_;
};

}  // namespace

nlohmann::json packet_counters_json(const QueryCounters& c, std::size_t kd_nodes, bool triangle_culling) {
    const double packets = c.packets ? double(c.packets) : 1.0;
    return {{"cells_per_packet", double(c.mlrta.ep_steps + c.packet_steps) / packets},
            {"ep_cells_per_packet", double(c.mlrta.ep_steps) / packets},
            {"xp_cells_per_packet", double(c.packet_steps) / packets},
            {"intersections_per_packet", double(c.triangle_tests) / packets},
            {"packets", c.packets},
            {"tiles", c.mlrta.tiles},
            {"divergent_tiles", c.mlrta.divergent_tiles},
            {"single_rays", c.single_rays},
            {"blocked_tiles", c.mlrta.blocked_tiles},
            {"triangle_culling", triangle_culling},
            {"kd_nodes", kd_nodes}};
}

std::unique_ptr<Engine> make_kd1_engine() { return std::make_unique<Kd1Engine>(); }
std::unique_ptr<Engine> make_kd16_engine() { return std::make_unique<Kd16Engine>(); }
std::unique_ptr<Engine> make_brute_engine() { return std::make_unique<BruteEngine>(); }

}  // namespace beamtrace::workload
