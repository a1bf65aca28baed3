// mlrta: tiles of beams, entry-point search, tile splitting, interval traversal from the entry
// points, when the rays form an image; the library's packet queries otherwise. Shadow rays are
// traced from their light by the library itself (Mlrta::occluded).
#include <chrono>
#include <mutex>

#include "engines/engine_registry.hpp"

namespace beamtrace::workload {

nlohmann::json mlrta_settings_json(const MlrtaSettings& s) {
    const MlrtaExperimental& x = s.experimental;
    return {{"initial_tile", s.initial_tile},
            {"split_factor", s.split_factor},
            {"min_tile", s.min_tile},
            {"frustum_test", x.frustum_test == FrustumTest::inverse ? "inverse" : "direct"},
            {"ep_search", x.ep_search == EpSearch::top_down ? "top-down" : "bifurcation-stack"},
            {"ep_triangles", x.ep_triangles},
            {"ep_resume", x.ep_resume},
            {"stuck_stop", x.stop_when_stuck},
            {"stuck_retry", x.retry_stuck},
            {"xp_packets", x.xp_packets},
            {"shadow_bvh", x.shadow_bvh}};
}

namespace {

class MlrtaEngine : public Engine {
public:
    std::string name() const override { return "mlrta"; }
    void build(const Scene& scene, const EngineOptions& options) override {
        tree_ = std::make_unique<KdTree>(KdTree::build(scene, options.kd_rules, options.build_progress));
        const auto start = std::chrono::steady_clock::now();
        mlrta_ = std::make_unique<Mlrta>(*tree_, options.mlrta);
        tables_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        bvh_prepared_ = false;  // a new Mlrta: its wide BVH is not built
    }
    // Occlusion rays: the wide BVH of MlrtaExperimental::shadow_bvh, built here and counted as build
    // time (the library builds it at the first occlusion query otherwise).
    void prepare(const RaySet& rays) override {
        if (closest_hit(rays.mode) || bvh_prepared_) return;
        const auto start = std::chrono::steady_clock::now();
        mlrta_->prepare_occlusion();
        tables_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        bvh_prepared_ = true;
    }
    // The tree and MLRTA's tables over it (subtree sizes, covered leaves, the tree's packet tables;
    // the wide BVH of shadow packets when occlusion rays were prepared).
    double build_seconds() const override { return tree_->stats().build_seconds + tables_seconds_; }
    std::size_t memory_bytes() const override { return tree_->stats().bytes + mlrta_->memory_bytes(); }

    void trace(const RaySet& rays, bool closest, EngineAnswers& a, int threads) const override {
        query(rays, closest, a, QueryOptions{threads, nullptr});
    }

    nlohmann::json stats(const RaySet& rays) const override {
        QueryCounters c;
        EngineAnswers a;
        query(rays, closest_hit(rays.mode), a, QueryOptions{1, &c});
        nlohmann::json j =
            packet_counters_json(c, tree_->stats().nodes, mlrta_->settings().experimental.triangle_culling);
        j.update(mlrta_settings_json(mlrta_->settings()));
        return j;
    }

    bool tile_complexity(const RaySet& rays, std::vector<TileInfo>& tiles) const override {
        if (rays.packets_x == 0) return false;
        std::vector<PacketHits16> hits(rays.packets.size());
        std::mutex mutex;
        mlrta_->intersect(grid(rays), hits, {}, [&](const TileInfo& t) {
            std::lock_guard<std::mutex> lock(mutex);
            tiles.push_back(t);
        });
        return true;
    }

private:
    static PacketGrid grid(const RaySet& rays) {
        return PacketGrid{rays.packets.data(), rays.packets_x, rays.packets_y};
    }

    // Tiles of beams when the packets form an image; packet by packet otherwise.
    void query(const RaySet& rays, bool closest, EngineAnswers& a, const QueryOptions& options) const {
        if (rays.packets_x == 0) return answer_packets(*mlrta_, rays, closest, a, options);
        a.form = EngineAnswers::Form::packets;
        if (closest) {
            a.packet_hits.resize(rays.packets.size());
            mlrta_->intersect(grid(rays), a.packet_hits, options);
        } else {
            a.packet_occluded.resize(rays.packets.size());
            mlrta_->occluded(grid(rays), a.packet_occluded, options);
        }
    }

    double tables_seconds_ = 0.0;
    bool bvh_prepared_ = false;
    std::unique_ptr<KdTree> tree_;
    std::unique_ptr<Mlrta> mlrta_;
};

}  // namespace

std::unique_ptr<Engine> make_mlrta_engine() { return std::make_unique<MlrtaEngine>(); }

}  // namespace beamtrace::workload
