// embree-mb, embree-refit, embree-dynamic: Embree on the animation itself (oracle/embree_animation.hpp),
// at its best: rays prebuilt (untimed) in Embree's packet and stream layouts with their times, each
// query timed in both layouts with both context flags, the fastest counted.
#include <chrono>

#include "engines/animated_engine.hpp"
#include "engines/parallel.hpp"
#include "oracle/embree_native_rays.hpp"

namespace beamtrace::workload {

namespace {

using oracle::EmbreeContextFlag;
using oracle::EmbreeLayout;
using oracle::EmbreeMotion;
using oracle::EmbreeNativeRays;

const char* motion_name(EmbreeMotion motion) {
    switch (motion) {
        case EmbreeMotion::motion_blur:
            return "embree-mb";
        case EmbreeMotion::dynamic_refit:
            return "embree-refit";
        case EmbreeMotion::dynamic_rebuild:
            return "embree-dynamic";
    }
    return "?";
}

class EmbreeMotionEngine : public AnimatedEngine {
public:
    explicit EmbreeMotionEngine(EmbreeMotion motion) : motion_(motion) {}
    std::string name() const override { return motion_name(motion_); }
    // Even the dynamic kinds keep the static triangles' structure across frames.
    bool rebuilds_per_frame() const override { return false; }

    double start(const AnimatedScene& scene, const EngineOptions& options) override {
        embree_ = std::make_unique<oracle::EmbreeAnimation>(scene, motion_, options.embree_build_threads);
        memory_peak_ = embree_->memory_bytes();
        return embree_->build_seconds();
    }

    FrameSeconds trace_frame(const FrameRays& frame, FrameAnswers& answers, int threads) override {
        FrameSeconds seconds;
        answers.primary.assign(frame.primary.slots(), Hit{});
        answers.shadow.assign(frame.shadow.slots(), 0);
        if (motion_ == EmbreeMotion::motion_blur) {
            // Every ray at once: the time goes with the ray.
            seconds.trace += query(frame.primary, frame.slot_time, answers.primary, threads);
            seconds.trace += query(frame.shadow, frame.slot_time, answers.shadow, threads);
            return seconds;
        }
        const bool one_time = frame.times.size() == 1;
        std::vector<Hit> hits;
        std::vector<std::uint8_t> occluded;
        for (const float t : frame.times) {
            seconds.build += embree_->set_time(t);
            memory_peak_ = std::max(memory_peak_, embree_->memory_bytes());
            const RaySet primary = one_time ? RaySet{} : rays_at_time(frame.primary, frame.slot_time, t);
            const RaySet shadow = one_time ? RaySet{} : rays_at_time(frame.shadow, frame.slot_time, t);
            seconds.trace += query(one_time ? frame.primary : primary, frame.slot_time, hits, threads);
            seconds.trace += query(one_time ? frame.shadow : shadow, frame.slot_time, occluded, threads);
            for (std::size_t s = 0; s < hits.size(); ++s)
                if (frame.slot_time[s] == t) {
                    answers.primary[s] = hits[s];
                    answers.shadow[s] = occluded[s];
                }
        }
        return seconds;
    }

    std::size_t memory_bytes() const override { return std::max(memory_peak_, embree_->memory_bytes()); }

private:
    // One query over the rays (closest hits into std::vector<Hit>, occlusion into std::vector<uint8_t>),
    // timed in each layout and context flag; returns the fastest pass's seconds.
    template <class Answer>
    double query(const RaySet& rays, const std::vector<float>& slot_time, std::vector<Answer>& out, int threads) {
        constexpr bool closest = std::is_same_v<Answer, Hit>;
        double best = 1e300;
        for (const EmbreeLayout layout : {EmbreeLayout::packet16, EmbreeLayout::stream}) {
            EmbreeNativeRays native(*embree_, layout, rays.packets, closest, slot_time);
            for (const EmbreeContextFlag flag : {EmbreeContextFlag::coherent, EmbreeContextFlag::incoherent}) {
                native.reset();
                const auto begin = std::chrono::steady_clock::now();
                for_packet_ranges(native.units(), threads,
                                  [&](std::size_t b, std::size_t e) { native.trace(flag, b, e); });
                best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count());
            }
            if (layout == EmbreeLayout::stream) {
                if constexpr (closest)
                    native.hits(out);
                else
                    native.occluded(out);
            }
        }
        return best;
    }

    EmbreeMotion motion_;
    std::unique_ptr<oracle::EmbreeAnimation> embree_;
    std::size_t memory_peak_ = 0;
};

}  // namespace

std::unique_ptr<AnimatedEngine> make_embree_motion_engine(oracle::EmbreeMotion motion) {
    return std::make_unique<EmbreeMotionEngine>(motion);
}

}  // namespace beamtrace::workload
