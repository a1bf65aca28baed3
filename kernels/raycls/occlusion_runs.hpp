#pragma once
// Occlusion rays of a light buffer tested in runs that share a grid cell (beyond the thesis;
// docs/raycls.md, "Runs of shadow rays").
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "common/triangle_kernels.hpp"
#include "common/watertight_ray.hpp"
#include "kdtree/packet/packet_setup_kernels.hpp"
#include "raycls/candidate_tests.hpp"

namespace beamtrace::raycls {

// Any hit: a Hit whose hit() is true (any id: only hit() is read).
inline Hit any_hit(bool hit) {
    Hit h;
    if (hit) h.triangle = 0;
    return h;
}

// Occlusion rays of light buffers in runs that share a grid cell (neighbouring pixels' shadow rays),
// up to 16 a run: each candidate tested against the run's rays at once (one 16-ray watertight test),
// in the list's order until every ray is occluded or the candidates' keys pass every ray's stop. A
// ray is answered as any_candidate answers it: every candidate at or before its own stop is tested
// (the run may test a few more, beyond its stop but before another ray's: a hit there is a hit of
// its segment all the same). Runs of fewer than kMinRunRays go one by one.
template <bool kCount, class Out>
class OcclusionRuns {
public:
    static constexpr int kMinRunRays = 4;

    // out(index, Hit) takes the answers.
    OcclusionRuns(const TriangleKernels& kernels, const kdtree::PacketSetupKernels& setup, Out& out,
                  QueryCounters* counters)
        : kernels_(kernels), setup_(setup), out_(out), counters_(counters) {}

    // Ray `index`, whose grid cell holds `items`, needing no test beyond key `stop` (locate()).
    void add(std::size_t index, const Ray& ray, std::span<const Candidate> items, float stop) {
        if (count_ > 0 && (count_ == 16 || !holds(items))) flush();
        if (count_ == 0) items_ = items;
        index_[count_] = index;
        stop_[count_] = stop;
        packet_.set_ray(count_, ray);
        ++count_;
    }

    bool holds(std::span<const Candidate> items) const {
        return count_ > 0 && items.data() == items_.data() && items.size() == items_.size();
    }

    void flush() {
        if (count_ == 0) return;
        if (count_ < kMinRunRays) {
            for (int i = 0; i < count_; ++i)
                out_(index_[i], any_hit(any_candidate<kCount>(kernels_, items_, packet_.ray(i), stop_[i], counters_)));
            count_ = 0;
            return;
        }
        if constexpr (kCount) counters_->raycls.run_rays += std::uint64_t(count_);
        packet_.active = (1u << count_) - 1u;
        setup_.watertight(packet_, wp_);
        wp_.active = packet_.active;
        float stop = stop_[0];
        for (int i = 1; i < count_; ++i) stop = std::max(stop, stop_[i]);
        std::uint32_t occluded = 0;
        for (const Candidate& c : items_) {
            if (c.key > stop) break;
            LaneHits h;
            kernels_.packet_x1(wp_, c.corners, h);
            if constexpr (kCount) {
                const auto lanes = std::uint64_t(__builtin_popcount(wp_.active));
                counters_->raycls.candidates += lanes;
                counters_->triangle_tests += lanes;
            }
            occluded |= h.mask;
            wp_.active &= ~h.mask;
            if (wp_.active == 0) break;
        }
        for (int i = 0; i < count_; ++i) out_(index_[i], any_hit((occluded >> i) & 1u));
        count_ = 0;
    }

private:
    const TriangleKernels& kernels_;
    const kdtree::PacketSetupKernels& setup_;
    Out& out_;
    QueryCounters* counters_;
    std::span<const Candidate> items_;
    int count_ = 0;
    std::size_t index_[16];
    float stop_[16];
    Packet16 packet_{};  // lanes past a run's rays: zeros or an earlier run's rays (never garbage)
    WatertightPacket16 wp_;
};

}  // namespace beamtrace::raycls
