// embree1, embree16 and embree-stream: Embree 3 used as its manual advises, the anchor of every
// speed ratio. Rays are prebuilt (untimed) in Embree's own layout (oracle/embree_native_rays.hpp),
// a timed pass holds Embree's query calls only, and each pass is timed with both context flags.
#include <chrono>

#include "oracle/embree_native_rays.hpp"
#include "engines/engine_registry.hpp"
#include "engines/parallel.hpp"

namespace beamtrace::workload {
namespace {

using oracle::EmbreeContextFlag;
using oracle::EmbreeLayout;
using oracle::EmbreeNativeRays;

constexpr EmbreeContextFlag kFlags[] = {EmbreeContextFlag::coherent, EmbreeContextFlag::incoherent};

const char* engine_name(EmbreeLayout layout) {
    switch (layout) {
        case EmbreeLayout::single:
            return "embree1";
        case EmbreeLayout::packet16:
            return "embree16";
        case EmbreeLayout::stream:
            return "embree-stream";
    }
    return "?";
}

// Embree's queries over every unit of the rays, split over threads.
void trace_all(EmbreeNativeRays& native, EmbreeContextFlag flag, int threads) {
    for_packet_ranges(native.units(), threads, [&](std::size_t b, std::size_t e) { native.trace(flag, b, e); });
}

void answers_of(const EmbreeNativeRays& native, bool closest, EngineAnswers& answers) {
    answers.form = EngineAnswers::Form::slots;
    if (closest)
        native.hits(answers.hits);
    else
        native.occluded(answers.occluded);
}

class EmbreeEngine : public Engine {
public:
    explicit EmbreeEngine(EmbreeLayout layout) : layout_(layout) {}
    std::string name() const override { return engine_name(layout_); }
    void build(const Scene& scene, const EngineOptions& options) override {
        native_.reset();  // its rays point into the old Embree scene
        prepared_for_ = nullptr;
        oracle_ = std::make_unique<oracle::EmbreeOracle>(scene, oracle::EmbreeSceneOptions{options.embree_robust, options.embree_build_threads});
    }
    double build_seconds() const override { return oracle_->build_seconds(); }
    std::size_t memory_bytes() const override { return oracle_->memory_bytes(); }

    // Untimed use (tests, pictures): the rays converted for this call, the coherent flag.
    void trace(const RaySet& rays, bool closest, EngineAnswers& answers, int threads) const override {
        EmbreeNativeRays native(*oracle_, layout_, rays.packets, closest);
        trace_all(native, EmbreeContextFlag::coherent, threads);
        answers_of(native, closest, answers);
    }

    void prepare(const RaySet& rays) override {
        // The same ray set as last time (its packets still at the same place, the same size and mode).
        if (native_ && prepared_for_ == &rays && prepared_packets_ == rays.packets.data() &&
            prepared_slots_ == rays.slots() && prepared_mode_ == rays.mode)
            return;
        native_.reset();  // free the old layout before making the new one
        native_ = std::make_unique<EmbreeNativeRays>(*oracle_, layout_, rays.packets, closest_hit(rays.mode));
        prepared_for_ = &rays;
        prepared_packets_ = rays.packets.data();
        prepared_slots_ = rays.slots();
        prepared_mode_ = rays.mode;
    }
    std::vector<std::string> timing_variants() const override {
        return {oracle::to_string(kFlags[0]), oracle::to_string(kFlags[1])};
    }
    std::string timing_variant_key() const override { return "context_flag"; }
    double timed_pass(const RaySet& rays, EngineAnswers& answers, int threads, int variant) override {
        prepare(rays);
        native_->reset();
        const auto start = std::chrono::steady_clock::now();
        trace_all(*native_, kFlags[variant], threads);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        answers_of(*native_, closest_hit(rays.mode), answers);
        return seconds;
    }

    nlohmann::json stats(const RaySet& rays) const override {
        nlohmann::json j = {
            {"embree_triangles", oracle_->embree_triangle_count()},
            {"robust", oracle_->robust()},
            {"layout", layout_ == EmbreeLayout::single     ? "RTCRayHit per ray, rtcIntersect1"
                       : layout_ == EmbreeLayout::packet16 ? "RTCRayHit16 per 4x4 packet, rtcIntersect16"
                                                           : "RTCRayHit array, rtcIntersect1M"}};
        if (!closest_hit(rays.mode)) {
            j["layout"] = layout_ == EmbreeLayout::single     ? "RTCRay per ray, rtcOccluded1"
                          : layout_ == EmbreeLayout::packet16 ? "RTCRay16 per 4x4 packet, rtcOccluded16"
                                                              : "RTCRay array, rtcOccluded1M";
        }
        if (native_ && prepared_for_ == &rays) j["ray_layout_bytes"] = native_->bytes();
        return j;
    }

private:
    EmbreeLayout layout_;
    std::unique_ptr<oracle::EmbreeOracle> oracle_;
    std::unique_ptr<EmbreeNativeRays> native_;  // the rays of the timed passes, in Embree's layout
    const RaySet* prepared_for_ = nullptr;
    const Packet16* prepared_packets_ = nullptr;
    std::size_t prepared_slots_ = 0;
    Mode prepared_mode_ = Mode::primary;
};

}  // namespace

std::unique_ptr<Engine> make_embree_engine(oracle::EmbreeLayout layout) {
    return std::make_unique<EmbreeEngine>(layout);
}

}  // namespace beamtrace::workload
