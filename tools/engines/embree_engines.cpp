// embree1, embree16 and embree-stream: Embree 3 used as its manual advises, the anchor of every
// speed ratio. Rays are prebuilt (untimed) in Embree's own layout (oracle/embree_native_rays.hpp),
// a timed pass holds Embree's query calls only, and each pass is timed with both context flags.
//
// A ray set of more than EngineOptions::embree_part_packets packets (over a million rays, e.g. 1024x1024 AO with 16 rays a
// pixel) is prebuilt one part at a time inside each pass: part k converted (untimed), its queries
// timed, its answers copied out, its layout freed before part k + 1 is made. Prebuilt whole, the
// three engines' layouts of 16.8 million AO rays held 2.9 GB next to the engine under test
// (docs/oracle.md); in parts each holds at most one part's (about 60 MB) and only during its pass.
#include <algorithm>
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
        const oracle::EmbreeSceneOptions wanted{options.embree_robust, options.embree_build_threads};
        // Built here either way, so that the build is timed and counted as this engine's; when the
        // caller holds the same scene built alike, this copy goes at once and the passes trace that one.
        auto own = std::make_shared<oracle::EmbreeOracle>(scene, wanted);
        build_seconds_ = own->build_seconds();
        memory_bytes_ = own->memory_bytes();
        scene_shared_ = options.embree_scene && options.embree_scene->options() == wanted &&
                        options.embree_scene->embree_triangle_count() == own->embree_triangle_count();
        if (scene_shared_)
            oracle_ = options.embree_scene;
        else
            oracle_ = std::move(own);
        part_packets_ = std::max<std::size_t>(options.embree_part_packets, 1);
    }
    double build_seconds() const override { return build_seconds_; }
    std::size_t memory_bytes() const override { return memory_bytes_; }

    // Untimed use (tests, pictures): the rays converted for this call, the coherent flag.
    void trace(const RaySet& rays, bool closest, EngineAnswers& answers, int threads) const override {
        EmbreeNativeRays native(*oracle_, layout_, rays.packets, closest);
        trace_all(native, EmbreeContextFlag::coherent, threads);
        answers_of(native, closest, answers);
    }

    void prepare(const RaySet& rays) override {
        if (rays.packets.size() > part_packets_) {  // prebuilt part by part in each pass
            native_.reset();
            prepared_for_ = nullptr;
            return;
        }
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
        if (rays.packets.size() > part_packets_) return timed_pass_in_parts(rays, answers, threads, variant);
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
            {"scene_shared", scene_shared_},
            {"layout", layout_ == EmbreeLayout::single     ? "RTCRayHit per ray, rtcIntersect1"
                       : layout_ == EmbreeLayout::packet16 ? "RTCRayHit16 per 4x4 packet, rtcIntersect16"
                                                           : "RTCRayHit array, rtcIntersect1M"}};
        if (!closest_hit(rays.mode)) {
            j["layout"] = layout_ == EmbreeLayout::single     ? "RTCRay per ray, rtcOccluded1"
                          : layout_ == EmbreeLayout::packet16 ? "RTCRay16 per 4x4 packet, rtcOccluded16"
                                                              : "RTCRay array, rtcOccluded1M";
        }
        if (native_ && prepared_for_ == &rays) j["ray_layout_bytes"] = native_->bytes();
        if (part_bytes_ > 0 && rays.packets.size() > part_packets_) {
            j["ray_layout_bytes"] = part_bytes_;  // the most held at once: one part's
            j["ray_layout_part_rays"] = part_packets_ * 16;
        }
        return j;
    }

private:
    double timed_pass_in_parts(const RaySet& rays, EngineAnswers& answers, int threads, int variant) {
        const bool closest = closest_hit(rays.mode);
        const std::span<const Packet16> packets(rays.packets);
        answers.form = EngineAnswers::Form::slots;
        if (closest)
            answers.hits.resize(rays.slots());
        else
            answers.occluded.resize(rays.slots());
        double seconds = 0.0;
        for (std::size_t first = 0; first < packets.size(); first += part_packets_) {
            const std::size_t count = std::min(part_packets_, packets.size() - first);
            EmbreeNativeRays part(*oracle_, layout_, packets.subspan(first, count), closest);
            part_bytes_ = std::max(part_bytes_, part.bytes());
            const auto start = std::chrono::steady_clock::now();
            trace_all(part, kFlags[variant], threads);
            seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (closest)
                part.hits(std::span<Hit>(answers.hits).subspan(first * 16, count * 16));
            else
                part.occluded(std::span<std::uint8_t>(answers.occluded).subspan(first * 16, count * 16));
        }
        return seconds;
    }

    EmbreeLayout layout_;
    std::shared_ptr<const oracle::EmbreeOracle> oracle_;  // its own scene, or the caller's built alike
    double build_seconds_ = 0.0;
    std::size_t memory_bytes_ = 0;
    bool scene_shared_ = false;  // tracing the caller's scene (EngineOptions::embree_scene)
    std::unique_ptr<EmbreeNativeRays> native_;  // the rays of the timed passes, in Embree's layout
    const RaySet* prepared_for_ = nullptr;
    const Packet16* prepared_packets_ = nullptr;
    std::size_t prepared_slots_ = 0;
    Mode prepared_mode_ = Mode::primary;
    std::size_t part_packets_ = EngineOptions::kDefaultEmbreePartPackets;
    std::size_t part_bytes_ = 0;  // the largest part's layout (sets prebuilt in parts)
};

}  // namespace

std::unique_ptr<Engine> make_embree_engine(oracle::EmbreeLayout layout) {
    return std::make_unique<EmbreeEngine>(layout);
}

}  // namespace beamtrace::workload
