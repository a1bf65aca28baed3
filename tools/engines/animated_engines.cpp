// The animated engines' registry, and the per-time rebuild that turns any static engine into one.
#include <algorithm>
#include <chrono>
#include <deque>

#include "beamtrace/error.hpp"
#include "engines/animated_engine.hpp"
#include "report/wall_clock.hpp"

namespace beamtrace::workload {

namespace {

using report::seconds_since;

// Copies the slots of `from` whose time is t into `into` (per slot, same size).
template <class T>
void merge_at_time(const std::vector<T>& from, const std::vector<float>& slot_time, float t, std::vector<T>& into) {
    for (std::size_t s = 0; s < from.size(); ++s)
        if (slot_time[s] == t) into[s] = from[s];
}

// A static engine rebuilt on at(t) for each distinct time of a frame: the snapshot and the build are
// the frame's build time; the queries (the fastest of the engine's timing variants) its trace time.
class RebuildEngine : public AnimatedEngine {
public:
    explicit RebuildEngine(std::string name) : name_(std::move(name)), engine_(make_engine(name_)) {}
    std::string name() const override { return name_; }
    bool rebuilds_per_frame() const override { return true; }

    double start(const AnimatedScene& scene, const EngineOptions& options) override {
        scene_ = std::make_unique<AnimatedScene>(scene);
        options_ = options;
        return 0.0;
    }

    FrameSeconds trace_frame(const FrameRays& frame, FrameAnswers& answers, int threads) override {
        FrameSeconds seconds;
        answers.primary.assign(frame.primary.slots(), Hit{});
        answers.shadow.assign(frame.shadow.slots(), 0);
        const bool one_time = frame.times.size() == 1;
        std::deque<RaySet> subsets;
        for (const float t : frame.times) {
            const auto begin = std::chrono::steady_clock::now();
            {
                const Scene snapshot = scene_->at(t);
                engine_->build(snapshot, options_);
            }
            seconds.build += seconds_since(begin);
            memory_ = std::max(memory_, engine_->memory_bytes());
            // Each time's subsets live until the frame is done: engines know prepared rays by address.
            if (!one_time) {
                subsets.push_back(rays_at_time(frame.primary, frame.slot_time, t));
                subsets.push_back(rays_at_time(frame.shadow, frame.slot_time, t));
            }
            for (int which = 0; which < 2; ++which) {
                const RaySet& rays = one_time ? (which == 0 ? frame.primary : frame.shadow)
                                              : subsets[subsets.size() - 2 + std::size_t(which)];
                // What prepare() builds for these rays and counts as the engine's build (mlrta's wide
                // BVH of occlusion packets) is build time here too; ray layouts (Embree's) are not.
                const double built_before = engine_->build_seconds();
                engine_->prepare(rays);
                seconds.build += std::max(0.0, engine_->build_seconds() - built_before);
                memory_ = std::max(memory_, engine_->memory_bytes());
                const std::size_t variants = std::max<std::size_t>(1, engine_->timing_variants().size());
                double best = 1e300;
                EngineAnswers a;
                for (std::size_t v = 0; v < variants; ++v)
                    best = std::min(best, engine_->timed_pass(rays, a, threads, int(v)));
                seconds.trace += best;
                if (which == 0)
                    merge_at_time(a.hits, frame.slot_time, t, answers.primary);
                else
                    merge_at_time(a.occluded, frame.slot_time, t, answers.shadow);
            }
        }
        return seconds;
    }

    // The most one build held (the engine keeps one snapshot's structure at a time).
    std::size_t memory_bytes() const override { return memory_; }

private:
    std::string name_;
    std::unique_ptr<Engine> engine_;
    std::unique_ptr<AnimatedScene> scene_;
    EngineOptions options_;
    std::size_t memory_ = 0;
};

}  // namespace

RaySet rays_at_time(const RaySet& rays, const std::vector<float>& slot_time, float t) {
    RaySet out = rays;
    out.ray_count = 0;
    for (std::size_t p = 0; p < out.packets.size(); ++p) {
        std::uint32_t active = 0;
        for (std::uint32_t m = rays.packets[p].active & 0xFFFFu; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            if (slot_time[p * 16 + std::size_t(i)] == t) active |= 1u << i;
        }
        out.packets[p].active = active;
        out.ray_count += std::size_t(__builtin_popcount(active));
    }
    return out;
}

const std::vector<std::string>& animated_engine_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n = {"raycls-st", "raycls-st-packets", "embree-mb", "embree-refit", "embree-dynamic"};
        for (const std::string& s : engine_names()) n.push_back(s);
        return n;
    }();
    return names;
}

std::unique_ptr<AnimatedEngine> make_animated_engine(const std::string& name) {
    if (name == "raycls-st") return make_space_time_engine(false);
    if (name == "raycls-st-packets") return make_space_time_engine(true);
    if (name == "embree-mb") return make_embree_motion_engine(oracle::EmbreeMotion::motion_blur);
    if (name == "embree-refit") return make_embree_motion_engine(oracle::EmbreeMotion::dynamic_refit);
    if (name == "embree-dynamic") return make_embree_motion_engine(oracle::EmbreeMotion::dynamic_rebuild);
    for (const std::string& s : engine_names())
        if (s == name) return make_rebuild_engine(name);
    std::string known;
    for (const std::string& n : animated_engine_names()) known += (known.empty() ? "" : ", ") + n;
    throw Error("unknown engine '" + name + "' for an animation (known: " + known + ")");
}

std::unique_ptr<AnimatedEngine> make_rebuild_engine(const std::string& static_engine) {
    return std::make_unique<RebuildEngine>(static_engine);
}

}  // namespace beamtrace::workload
