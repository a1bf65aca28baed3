// stream (the library's StreamTracer: arbitrary rays hashed, sorted and grouped, then traced by the
// kd-tree, rays in no group by a wide BVH) and embree-sorted (Embree's single-ray calls fed the
// stream tracer's sorted order, the sort untimed: what sorting alone gives Embree, so that the gain
// of sorting and the gain of the stream tracer's kernels are told apart; not an anchor).
#include <chrono>

#include "beamtrace/error.hpp"
#include "beamtrace/stream.hpp"
#include "engines/active_rays.hpp"
#include "engines/engine_registry.hpp"
#include "engines/parallel.hpp"
#include "oracle/embree_native_rays.hpp"

namespace beamtrace::workload {
namespace {

class StreamEngine : public Engine {
public:
    std::string name() const override { return "stream"; }
    void build(const Scene& scene, const EngineOptions& options) override {
        prepared_.forget();
        tree_ = build_packet_tree(scene, options);
        tracer_ = std::make_unique<StreamTracer>(*tree_, options.stream);
    }
    // The kd-tree's build and the wide BVH's (StreamSettings::wide_bvh).
    double build_seconds() const override { return tree_->stats().build_seconds + tracer_->wide_bvh_build_seconds(); }
    std::size_t memory_bytes() const override {
        return tree_->stats().bytes + tree_->packet_table_bytes() + tracer_->wide_bvh_bytes();
    }

    void prepare(const RaySet& rays) override { prepared_.prepare(rays); }

    // The timed region is one stream call over the active rays in the ray set's order: keys, sort,
    // groups, tracing and the answers in input order.
    void trace(const RaySet& rays, bool closest, EngineAnswers& a, int threads) const override {
        prepared_.answer(*tracer_, rays, closest, a, QueryOptions{threads, nullptr});
    }

    nlohmann::json stats(const RaySet& rays) const override {
        const ActiveRays in = active_rays(rays);
        const bool closest = closest_hit(rays.mode);
        EngineAnswers a;
        // One plain call timed (the share of sorting), one counted call (the counts and the sort time).
        const auto start = std::chrono::steady_clock::now();
        answer_rays(*tracer_, in, closest, a, QueryOptions{1, nullptr});
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        QueryCounters c;
        answer_rays(*tracer_, in, closest, a, QueryOptions{1, &c});
        const auto& s = c.stream;
        const double n = s.rays ? double(s.rays) : 1.0;
        const std::uint64_t groups = s.origin_groups + s.pencil_packets + s.loose_groups;
        const double sort_seconds = double(s.sort_nanoseconds) * 1e-9;
        nlohmann::json j = {
            {"sort_seconds", sort_seconds},
            {"sort_fraction", seconds > 0 ? sort_seconds / seconds : 0.0},
            {"groups", groups},
            {"mean_rays_per_group",
             groups ? double(s.origin_group_rays + s.pencil_rays + s.loose_group_rays) / double(groups) : 0.0},
            {"single_rays", s.single_rays},
            {"bucket_ordered_rays", s.bucket_ordered_rays},
            {"origin_groups", s.origin_groups},
            {"origin_group_rays", s.origin_group_rays},
            {"loose_groups", s.loose_groups},
            {"loose_group_rays", s.loose_group_rays},
            {"pencil_packets", s.pencil_packets},
            {"pencil_rays", s.pencil_rays},
            {"cells_per_ray", double(c.inner_steps + c.leaves + c.packet_steps + s.group_steps +
                                     s.group_unreached_planes + s.group_leaves) /
                                  n},
            {"group_steps_per_ray", double(s.group_steps) / n},
            {"group_unreached_planes_per_ray", double(s.group_unreached_planes) / n},
            {"triangle_tests_per_ray", double(c.triangle_tests) / n},
            // The calling thread's buffers of a call of these rays (docs/streams.md): keys, origin
            // hashes, order, sorted keys, sorted rays, the sort's 40-byte records of a ray and its
            // word (stream/ray_sort.hpp), groups, the answers by sorted position (at most: a stream
            // in buckets beyond the caches needs no hashes, order, sorted keys or sorted rays, only
            // each ray's position in the records).
            {"buffer_bytes",
             tracer_->settings().sort
                 ? s.rays * (4 + 4 + 4 + 4 + sizeof(Ray) + 40 + (closest ? sizeof(Hit) : 1)) + groups * 12
                 : 0},
            {"sort", tracer_->settings().sort},
            {"min_group_rays", tracer_->settings().min_group_rays},
            {"group_loose_rays", tracer_->settings().group_loose_rays},
            {"wide_bvh", tracer_->settings().wide_bvh},
            {"bucket_order", tracer_->settings().bucket_order},
            {"bvh_pencils", tracer_->settings().bvh_pencils},
            {"wide_bvh_bytes", tracer_->wide_bvh_bytes()},
            {"wide_bvh_build_seconds", tracer_->wide_bvh_build_seconds()}};
        j.update(tree_json(tree_->stats()));
        return j;
    }

private:
    std::unique_ptr<KdTree> tree_;
    std::unique_ptr<StreamTracer> tracer_;
    PreparedRays prepared_;
};

using oracle::EmbreeContextFlag;
using oracle::EmbreeLayout;
using oracle::EmbreeNativeRays;

class EmbreeSortedEngine : public Engine {
public:
    std::string name() const override { return "embree-sorted"; }
    void build(const Scene& scene, const EngineOptions& options) override {
        native_.reset();  // its rays point into the old Embree scene
        prepared_.forget();
        oracle_ = std::make_unique<oracle::EmbreeOracle>(
            scene, oracle::EmbreeSceneOptions{options.embree_robust, options.embree_build_threads});
        bounds_ = scene.bounds();
        settings_ = options.stream;
    }
    double build_seconds() const override { return oracle_->build_seconds(); }
    std::size_t memory_bytes() const override { return oracle_->memory_bytes(); }

    // The rays in the stream tracer's order, 16 to a packet, in Embree's single-ray layout (untimed).
    void prepare(const RaySet& rays) override {
        if (native_ && prepared_.ready_for(rays) && prepared_mode_ == rays.mode) return;
        native_.reset();
        prepared_.prepare(rays);
        prepared_mode_ = rays.mode;
        const bool closest = closest_hit(rays.mode);
        const std::vector<Ray>& in = prepared_.active.rays;
        std::vector<std::uint32_t> order(in.size());
        stream_order(in, bounds_, closest, order, settings_);
        sorted_packets_.assign((in.size() + 15) / 16, Packet16{});
        sorted_slots_.resize(in.size());
        for (std::size_t k = 0; k < in.size(); ++k) {
            sorted_packets_[k / 16].set_ray(int(k % 16), in[order[k]]);
            sorted_packets_[k / 16].active |= 1u << (k % 16);
            sorted_slots_[k] = prepared_.active.slots[order[k]];
        }
        native_ = std::make_unique<EmbreeNativeRays>(*oracle_, EmbreeLayout::single, sorted_packets_, closest);
    }
    std::vector<std::string> timing_variants() const override {
        return {oracle::to_string(EmbreeContextFlag::coherent), oracle::to_string(EmbreeContextFlag::incoherent)};
    }
    std::string timing_variant_key() const override { return "context_flag"; }
    double timed_pass(const RaySet& rays, EngineAnswers& answers, int threads, int variant) override {
        prepare(rays);
        native_->reset();
        const EmbreeContextFlag flag = variant == 0 ? EmbreeContextFlag::coherent : EmbreeContextFlag::incoherent;
        const auto start = std::chrono::steady_clock::now();
        for_packet_ranges(native_->units(), threads, [&](std::size_t b, std::size_t e) { native_->trace(flag, b, e); });
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        spread(rays, answers);
        return seconds;
    }
    void trace(const RaySet& rays, bool, EngineAnswers& answers, int threads) const override {
        if (!native_ || !prepared_.ready_for(rays))
            throw Error("embree-sorted: prepare() the ray set before tracing it");
        native_->reset();
        for_packet_ranges(native_->units(), threads,
                          [&](std::size_t b, std::size_t e) { native_->trace(EmbreeContextFlag::coherent, b, e); });
        spread(rays, answers);
    }
    nlohmann::json stats(const RaySet&) const override {
        return {{"layout",
                 "the stream tracer's sorted order (untimed sort), RTCRayHit / RTCRay per ray, "
                 "rtcIntersect1 / rtcOccluded1"},
                {"anchor", false}};
    }

private:
    // Embree's answers (per slot of the sorted packets) back to the ray set's slots.
    void spread(const RaySet& rays, EngineAnswers& answers) const {
        const bool closest = closest_hit(rays.mode);
        answers.form = EngineAnswers::Form::slots;
        if (closest) {
            std::vector<Hit> sorted;
            native_->hits(sorted);
            answers.hits.assign(rays.slots(), Hit{});
            for (std::size_t k = 0; k < sorted_slots_.size(); ++k) answers.hits[sorted_slots_[k]] = sorted[k];
        } else {
            std::vector<std::uint8_t> sorted;
            native_->occluded(sorted);
            answers.occluded.assign(rays.slots(), 0);
            for (std::size_t k = 0; k < sorted_slots_.size(); ++k) answers.occluded[sorted_slots_[k]] = sorted[k];
        }
    }

    std::unique_ptr<oracle::EmbreeOracle> oracle_;
    Box bounds_;
    StreamSettings settings_;
    PreparedRays prepared_;
    Mode prepared_mode_ = Mode::primary;
    std::vector<Packet16> sorted_packets_;
    std::vector<std::uint32_t> sorted_slots_;  // the ray set's slot of each sorted ray
    std::unique_ptr<EmbreeNativeRays> native_;
};

}  // namespace

std::unique_ptr<Engine> make_stream_engine() { return std::make_unique<StreamEngine>(); }
std::unique_ptr<Engine> make_embree_sorted_engine() { return std::make_unique<EmbreeSortedEngine>(); }

}  // namespace beamtrace::workload
