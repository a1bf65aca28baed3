// raycls-st: the library's SpaceTimeClassification over the frames of an animation. Built once
// (the static part's kd-tree); each frame's queries make the cells and time bins they need, and
// reuse the static cells earlier frames made. raycls-st-packets: the same with
// SpaceTimeSettings::static_packets (the static part by the kd-tree's packet traversal, kd16's; not
// the thesis), queried by 4x4 packets.
#include <chrono>

#include "beamtrace/space_time_classification.hpp"
#include "engines/active_rays.hpp"
#include "engines/animated_engine.hpp"
#include "report/wall_clock.hpp"

namespace beamtrace::workload {

namespace {

using report::seconds_since;

// The active rays of a set side by side with their times.
struct TimedRays {
    ActiveRays active;
    std::vector<float> times;
    TimedRays(const RaySet& rays, const std::vector<float>& slot_time) : active(active_rays(rays)) {
        times.reserve(active.slots.size());
        for (std::uint32_t s : active.slots) times.push_back(slot_time[s]);
    }
};

class SpaceTimeEngine : public AnimatedEngine {
public:
    explicit SpaceTimeEngine(bool packets) : packets_(packets) {}
    std::string name() const override { return packets_ ? "raycls-st-packets" : "raycls-st"; }
    bool rebuilds_per_frame() const override { return false; }

    double start(const AnimatedScene& scene, const EngineOptions& options) override {
        SpaceTimeSettings settings = options.space_time;
        settings.space = options.raycls;
        settings.static_packets = packets_;
        const auto begin = std::chrono::steady_clock::now();
        st_ = std::make_unique<SpaceTimeClassification>(scene, settings, options.kd_rules);
        return seconds_since(begin);
    }

    FrameSeconds trace_frame(const FrameRays& frame, FrameAnswers& answers, int threads) override {
        if (packets_) return trace_packets(frame, answers, threads);
        const TimedRays primary(frame.primary, frame.slot_time), shadow(frame.shadow, frame.slot_time);
        std::vector<Hit> hits(primary.active.rays.size());
        std::vector<std::uint8_t> occluded(shadow.active.rays.size());
        const QueryOptions options{threads, nullptr};
        const FrameSeconds seconds = timed_calls(frame, answers, [&] {
            st_->intersect(primary.active.rays, primary.times, hits, options);
            st_->occluded(shadow.active.rays, shadow.times, occluded, options);
        });
        for (std::size_t k = 0; k < hits.size(); ++k) answers.primary[primary.active.slots[k]] = hits[k];
        for (std::size_t k = 0; k < occluded.size(); ++k) answers.shadow[shadow.active.slots[k]] = occluded[k];
        return seconds;
    }

    std::size_t memory_bytes() const override {
        const SpaceTimeStats s = st_->stats();
        const KdTree& tree = st_->static_part().kd_tree();
        return tree.stats().bytes + tree.packet_table_bytes() + s.static_part.memory_bytes + s.moving_memory_bytes;
    }

    nlohmann::json stats() const override {
        const SpaceTimeStats s = st_->stats();
        const RayClsStats& c = s.static_part;
        return {{"moving_triangles", s.moving_triangles},
                {"time_bins", s.time_bins},
                {"bins_made", s.bins_made},
                {"bins_freed", s.bins_freed},
                {"bins_resident", s.bins_resident},
                {"moving_cells", s.moving_cells},
                {"moving_entries", s.moving_entries},
                {"moving_memory_bytes", s.moving_memory_bytes},
                {"moving_memory_peak_bytes", s.moving_memory_peak_bytes},
                {"static_cells_created", c.cells_created},
                {"static_cells_freed", c.cells_freed},
                {"static_candidate_entries", c.candidate_entries},
                {"static_memory_bytes", c.memory_bytes},
                {"static_memory_peak_bytes", c.memory_peak_bytes},
                {"static_light_buffers", c.light_buffers},
                {"static_lazy_build_seconds", c.lazy_build_seconds},
                {"kd_tree_bytes", st_->static_part().kd_tree().stats().bytes}};
    }

private:
    // The frame's two calls, timed; then the answers cleared to every slot (the caller fills them).
    template <class Calls>
    static FrameSeconds timed_calls(const FrameRays& frame, FrameAnswers& answers, Calls&& calls) {
        FrameSeconds seconds;
        const auto begin = std::chrono::steady_clock::now();
        calls();
        seconds.trace = seconds_since(begin);
        answers.primary.assign(frame.primary.slots(), Hit{});
        answers.shadow.assign(frame.shadow.slots(), 0);
        return seconds;
    }

    FrameSeconds trace_packets(const FrameRays& frame, FrameAnswers& answers, int threads) {
        std::vector<PacketHits16> hits(frame.primary.packets.size());
        std::vector<std::uint32_t> occluded(frame.shadow.packets.size());
        const QueryOptions options{threads, nullptr};
        const FrameSeconds seconds = timed_calls(frame, answers, [&] {
            st_->intersect(frame.primary.packets, frame.slot_time, hits, options);
            st_->occluded(frame.shadow.packets, frame.slot_time, occluded, options);
        });
        for (std::size_t slot = 0; slot < frame.primary.slots(); ++slot) {
            if (frame.primary.active(slot)) answers.primary[slot] = hits[slot / 16].hit(int(slot % 16));
            if (frame.shadow.active(slot)) answers.shadow[slot] = (occluded[slot / 16] >> (slot % 16)) & 1u;
        }
        return seconds;
    }

    bool packets_;
    std::unique_ptr<SpaceTimeClassification> st_;
};

}  // namespace

std::unique_ptr<AnimatedEngine> make_space_time_engine(bool packets) {
    return std::make_unique<SpaceTimeEngine>(packets);
}

}  // namespace beamtrace::workload
