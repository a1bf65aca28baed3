// kd16 (4x4 packets by interval traversal from the root: the paper's "no MLRT") and mlrta (tiles,
// beams, entry-point search, tile splitting, interval traversal from the entry points).
#include <chrono>
#include <cmath>
#include <mutex>

#include "beamtrace/error.hpp"
#include "beamtrace/mlrta.hpp"
#include "workload/engine_registry.hpp"
#include "workload/packet_answers.hpp"
#include "workload/parallel.hpp"

namespace beamtrace::workload {
namespace {

nlohmann::json counters_json(const MlrtaCounters& c) {
    const double packets = c.packets ? double(c.packets) : 1.0;
    return {{"cells_per_packet", double(c.ep_steps + c.xp_steps) / packets},
            {"ep_cells_per_packet", double(c.ep_steps) / packets},
            {"xp_cells_per_packet", double(c.xp_steps) / packets},
            {"intersections_per_packet", double(c.triangle_tests) / packets},
            {"packets", c.packets},
            {"tiles", c.tiles},
            {"divergent_tiles", c.divergent_tiles},
            {"single_rays", c.single_rays},
            {"blocked_tiles", c.blocked_tiles}};
}

// How far (in double) the reversed ray's far end lies from the original segment's start: the
// rounding of the new origin org + tfar * dir. Infinite or NaN when the ray cannot be reversed
// (tfar infinite).
double reversal_error(const Ray& ray, const Ray& back) {
    double e2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double start = double(ray.org[k]) + double(ray.dir[k]) * double(ray.tnear);
        const double end = double(back.org[k]) + double(back.dir[k]) * double(back.tfar);
        e2 += (end - start) * (end - start);
    }
    return std::sqrt(e2);
}

// Shadow rays end at the light: traced from there, they form beams with (nearly) one origin. A
// packet is reversed only if every ray's segment survives the reversal: its ends may move by at
// most 1e-6 of the scene's diagonal (a tenth of the comparison's grazing distance). Far from the
// world origin, or with an infinite tfar, the rounded segment would be another segment, so such
// packets are traced as they are (docs/robustness.md). Packets whose rays aim at several points
// are reversed ray by ray (reversed()) when that is exact enough, checked in double.
void reversed_packets(const RaySet& rays, const Box& bounds, int threads, std::vector<Packet16>& out) {
    const Float3 e = bounds.extent();  // the diagonal in double: float overflows from about 1e19 on
    const double tolerance = 1e-6 * std::sqrt(double(e.x) * e.x + double(e.y) * e.y + double(e.z) * e.z);
    out.resize(rays.packets.size());
    for_packet_ranges(rays.packets.size(), threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t p = begin; p < end; ++p) {
            const Packet16& in = rays.packets[p];
            if (reverse_towards_light(in, float(tolerance), out[p])) continue;
            out[p] = in;
            bool exact = true;
            for (std::uint32_t m = in.active & 0xFFFFu; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                const Ray ray = in.ray(i), back = reversed(ray);
                exact = exact && reversal_error(ray, back) <= tolerance;
                out[p].set_ray(i, back);
            }
            if (!exact) out[p] = in;
        }
    });
}

class MlrtaEngine : public Engine {
public:
    explicit MlrtaEngine(bool beams) : beams_(beams) {}
    std::string name() const override { return beams_ ? "mlrta" : "kd16"; }
    void build(const Scene& scene, const EngineOptions& options) override {
        tree_ = std::make_unique<KdTree>(KdTree::build(scene, options.kd_rules, options.build_progress));
        const auto start = std::chrono::steady_clock::now();
        mlrta_ = std::make_unique<Mlrta>(*tree_, options.mlrta);
        tables_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    // The tree and MLRTA's tables over it (subtree sizes, covered leaves, leaf geometry).
    double build_seconds() const override { return tree_->stats().build_seconds + tables_seconds_; }
    std::size_t memory_bytes() const override { return tree_->stats().bytes + mlrta_->memory_bytes(); }

    void intersect(const RaySet& rays, std::vector<Hit>& hits, int threads) const override {
        // The packets' hits go to a buffer kept between calls (a fresh 16 MB per call is page faults
        // on one thread) and are spread into `hits` by as many threads as the tracing.
        std::vector<PacketHits16>& out = packet_hits_;
        out.resize(rays.packets.size());
        trace(rays, rays.packets, threads, out.data(), nullptr, nullptr);
        hits.assign(rays.slots(), Hit{});
        for_packet_ranges(out.size(), threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t p = b; p < e; ++p) spread_hits(rays.packets[p], out[p], hits.data() + p * 16);
        });
    }

    void occluded(const RaySet& rays, std::vector<std::uint8_t>& occluded, int threads) const override {
        // Buffers kept between calls, like packet_hits_.
        if (beams_) reversed_packets(rays, tree_->scene().bounds(), threads, reversed_);
        std::vector<std::uint32_t>& bits = packet_bits_;
        bits.assign(rays.packets.size(), 0);
        trace(rays, beams_ ? reversed_ : rays.packets, threads, nullptr, bits.data(), nullptr);
        occluded.assign(rays.slots(), 0);
        for_packet_ranges(bits.size(), threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t p = b; p < e; ++p) spread_bits(bits[p], occluded.data() + p * 16);
        });
    }

    nlohmann::json stats(const RaySet& rays) const override {
        MlrtaCounters c;
        const bool closest = rays.mode == Mode::primary;
        std::vector<Packet16> packets;
        if (!closest && beams_) reversed_packets(rays, tree_->scene().bounds(), 1, packets);
        else packets = rays.packets;
        std::vector<PacketHits16> hits(closest ? packets.size() : 0);
        std::vector<std::uint32_t> bits(closest ? 0 : packets.size());
        trace(rays, packets, 1, closest ? hits.data() : nullptr, closest ? nullptr : bits.data(), &c);
        nlohmann::json j = counters_json(c);
        const MlrtaSettings& s = mlrta_->settings();
        j["initial_tile"] = s.initial_tile;
        j["split_factor"] = s.split_factor;
        j["min_tile"] = s.min_tile;
        j["frustum_test"] = s.frustum_test == FrustumTest::inverse ? "inverse" : "direct";
        j["ep_search"] = s.ep_search == EpSearch::top_down ? "top-down" : "bifurcation-stack";
        j["ep_triangles"] = s.ep_triangles;
        j["ep_resume"] = s.ep_resume;
        j["stuck_stop"] = s.stop_when_stuck;
        j["stuck_retry"] = s.retry_stuck;
        j["kd_nodes"] = tree_->stats().nodes;
        return j;
    }

    bool tile_complexity(const RaySet& rays, std::vector<TileInfo>& tiles) const override {
        if (!beams_ || rays.packets_x == 0) return false;
        std::vector<PacketHits16> hits(rays.packets.size());
        std::mutex mutex;
        const PacketGrid grid{rays.packets.data(), rays.packets_x, rays.packets_y};
        mlrta_->intersect(grid, hits.data(), 1, nullptr, [&](const TileInfo& t) {
            std::lock_guard<std::mutex> lock(mutex);
            tiles.push_back(t);
        });
        return true;
    }

private:
    // Tiles of beams when the packets form an image; packet by packet otherwise (and for kd16).
    void trace(const RaySet& rays, const std::vector<Packet16>& packets, int threads, PacketHits16* hits,
               std::uint32_t* bits, MlrtaCounters* counters) const {
        if (beams_ && rays.packets_x > 0) {
            const PacketGrid grid{packets.data(), rays.packets_x, rays.packets_y};
            if (hits) mlrta_->intersect(grid, hits, threads, counters);
            else mlrta_->occluded(grid, bits, threads, counters);
            return;
        }
        if (counters) {  // counting runs on one thread
            for (std::size_t p = 0; p < packets.size(); ++p) {
                if (hits) mlrta_->intersect_packet(packets[p], hits[p], counters);
                else bits[p] = mlrta_->occluded_packet(packets[p], counters);
            }
            return;
        }
        for_packet_ranges(packets.size(), threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t p = b; p < e; ++p) {
                if (hits) mlrta_->intersect_packet(packets[p], hits[p]);
                else bits[p] = mlrta_->occluded_packet(packets[p]);
            }
        });
    }

    bool beams_;
    double tables_seconds_ = 0.0;
    std::unique_ptr<KdTree> tree_;
    std::unique_ptr<Mlrta> mlrta_;
    // Per-call buffers kept from one call to the next (calls on one engine do not overlap).
    mutable std::vector<PacketHits16> packet_hits_;
    mutable std::vector<std::uint32_t> packet_bits_;
    mutable std::vector<Packet16> reversed_;
};

}  // namespace

std::unique_ptr<Engine> make_kd16_engine() { return std::make_unique<MlrtaEngine>(false); }
std::unique_ptr<Engine> make_mlrta_engine() { return std::make_unique<MlrtaEngine>(true); }

}  // namespace beamtrace::workload
