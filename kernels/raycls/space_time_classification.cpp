// SpaceTimeClassification (beamtrace/space_time_classification.hpp): the static part once, the
// moving triangles per time bin.
#include "beamtrace/space_time_classification.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <utility>
#include <vector>

#include "beamtrace/error.hpp"
#include "common/query_runner.hpp"
#include "mlrta/shadow_reversal.hpp"
#include "raycls/moving_bin.hpp"

namespace beamtrace {

void SpaceTimeSettings::validate() const {
    space.validate();
    if (time_bins < 0 || time_bins > 1024)
        throw Error("space-time classification: time_bins must be 0 (automatic) to 1024, not " +
                    std::to_string(time_bins));
    if (max_depth < 0 || max_depth > 8)
        throw Error("space-time classification: max_depth must be 0 to 8, not " + std::to_string(max_depth));
    if (min_candidates < 0)
        throw Error("space-time classification: min_candidates must be at least 0, not " +
                    std::to_string(min_candidates));
    if (keep_calls < 1)
        throw Error("space-time classification: keep_calls must be at least 1, not " + std::to_string(keep_calls));
    if (static_binned_above < 0)
        throw Error("space-time classification: static_binned_above must be at least 0 (0 = exact sweep), not " +
                    std::to_string(static_binned_above));
}

namespace {

// The rules of the static part's kd-tree: the caller's, binned above settings.static_binned_above
// unless they say otherwise.
KdBuildRules static_tree_rules(KdBuildRules rules, const SpaceTimeSettings& settings) {
    if (rules.binned_above == 0) rules.binned_above = settings.static_binned_above;
    return rules;
}

// About one bin per mean motion of a moving triangle's corners over its mean size.
int automatic_bins(const AnimatedScene& scene, const std::vector<std::uint32_t>& moving) {
    if (moving.empty()) return 1;
    double motion = 0.0, size = 0.0;
    const auto times = scene.times();
    for (std::uint32_t id : moving) {
        const Triangle first = scene.triangle_at(id, times.front());
        Box b;
        for (const Float3& p : {first.v0, first.v1, first.v2}) b.extend(p);
        size += double(b.diagonal());
        double path = 0.0;
        for (std::size_t k = 1; k < times.size(); ++k) {
            const Triangle a = scene.triangle_at(id, times[k - 1]), c = scene.triangle_at(id, times[k]);
            path += std::max({double(length(c.v0 - a.v0)), double(length(c.v1 - a.v1)), double(length(c.v2 - a.v2))});
        }
        motion += path;
    }
    if (size <= 0.0) return 1024;
    return int(std::clamp(std::lround(motion / size), 1L, 1024L));
}

}  // namespace

struct SpaceTimeClassification::Impl {
    AnimatedScene scene;
    SpaceTimeSettings settings;
    RayClassification still;
    std::vector<std::uint32_t> moving;
    int bins = 1;
    float start = 0.0f, span = 1.0f;
    float shared_point_size = 0.0f;  // largest box of shared points, as the static part's
    float apex_margin = 0.0f;        // light buffers' apex: the points' box grown by this
    // The moving triangles placed at the last call's times (PlacedTimes), and their bytes.
    mutable std::mutex placed_mutex;
    mutable std::vector<std::pair<float, std::shared_ptr<const std::vector<Triangle>>>> placed_last;
    mutable std::size_t placed_bytes = 0;
    mutable raycls::MovingContext context;
    mutable std::vector<std::atomic<raycls::MovingBin*>> slots;
    mutable std::mutex make_mutex;
    mutable std::shared_mutex use_mutex;
    mutable std::atomic<std::uint64_t> epoch{1}, bins_made{0}, bins_freed{0};

    Impl(const AnimatedScene& s, const SpaceTimeSettings& set, const KdBuildRules& rules)
        : scene(s), settings((set.validate(), set)), still(s.static_part(), set.space, static_tree_rules(rules, set)) {
        for (std::uint32_t t = 0; t < scene.triangle_count(); ++t)
            if (scene.is_moving(t)) moving.push_back(t);
        bins = settings.time_bins ? settings.time_bins : automatic_bins(scene, moving);
        start = scene.start_time();
        span = scene.end_time() - scene.start_time();
        context.scene = &scene;
        context.kernels = &triangle_kernels();
        context.moving = &moving;
        context.origins = scene.bounds();
        context.max_depth = settings.max_depth;
        context.min_candidates = settings.min_candidates;
        float scale = 1.0f;
        for (int k = 0; k < 3; ++k)
            scale = std::max({scale, std::fabs(context.origins.lower[k]), std::fabs(context.origins.upper[k])});
        context.origin_margin = double(scale) * 1e-5;
        context.direction_margin = 1e-6;
        shared_point_size = scene.bounds().diagonal() * raycls::kSharedPointFraction;
        apex_margin = scene.bounds().diagonal() * raycls::kApexMarginFraction;
        if (settings.static_packets) still.kd_tree().prepare_packet_queries();
        slots = std::vector<std::atomic<raycls::MovingBin*>>(std::size_t(bins));
        for (auto& b : slots) b.store(nullptr);
    }
    ~Impl() { free_bins(~std::uint64_t(0)); }

    int bin_of(float t) const {
        const float x = (t - start) / span * float(bins);
        return std::clamp(int(std::floor(x)), 0, bins - 1);
    }

    const raycls::MovingBin& bin(int i) const {
        std::atomic<raycls::MovingBin*>& slot = slots[std::size_t(i)];
        raycls::MovingBin* b = slot.load(std::memory_order_acquire);
        if (!b) {
            std::lock_guard<std::mutex> lock(make_mutex);
            b = slot.load(std::memory_order_acquire);
            if (!b) {
                const float t0 = start + span * float(i) / float(bins);
                const float t1 = i + 1 == bins ? scene.end_time() : start + span * float(i + 1) / float(bins);
                // The first and last bins also hold the clamped times outside the span.
                b = new raycls::MovingBin(context, i == 0 ? scene.start_time() : t0, t1);
                slot.store(b, std::memory_order_release);
                bins_made.fetch_add(1, std::memory_order_relaxed);
            }
        }
        const std::uint64_t e = epoch.load(std::memory_order_relaxed);
        if (b->last_used.load(std::memory_order_relaxed) != e) b->last_used.store(e, std::memory_order_relaxed);
        return *b;
    }

    // Frees the bins last used before `before` (only while no call runs).
    void free_bins(std::uint64_t before) const {
        for (auto& slot : slots) {
            raycls::MovingBin* b = slot.load();
            if (b && b->last_used.load() < before) {
                slot.store(nullptr);
                delete b;
                bins_freed.fetch_add(1, std::memory_order_relaxed);
            }
        }
    }

    void start_call() const {
        const std::uint64_t e = epoch.fetch_add(1) + 1;
        if (e <= std::uint64_t(settings.keep_calls)) return;
        std::unique_lock<std::shared_mutex> alone(use_mutex, std::try_to_lock);
        if (alone.owns_lock()) free_bins(e - std::uint64_t(settings.keep_calls));
    }
};

namespace {

void check_times(const char* what, std::size_t rays, std::span<const float> times) {
    if (times.size() != rays)
        throw Error(std::string(what) + ": " + std::to_string(times.size()) + " times for " + std::to_string(rays) +
                    " rays");
    for (std::size_t i = 0; i < times.size(); ++i)
        if (!std::isfinite(times[i]))
            throw Error(std::string(what) + ": ray " + std::to_string(i) + " has a time that is not finite");
}

// The moving triangles placed once at each time of a call, when the call has few distinct times
// and rays enough to pay for it (a frame's rays share a handful of jitter offsets): one placement
// per triangle and time instead of one per candidate test. Otherwise each test places its triangle.
class PlacedTimes {
public:
    PlacedTimes(const SpaceTimeClassification::Impl& impl, std::span<const float> times) {
        constexpr std::size_t kMaxTimes = 16;
        for (const float t : times) {
            if (std::find(times_.begin(), times_.end(), t) != times_.end()) continue;
            if (times_.size() == kMaxTimes) {
                times_.clear();
                return;
            }
            times_.push_back(t);
        }
        // The last call's placements are kept: a frame's calls (primary, then shadow rays) share
        // their times, so the second places nothing.
        std::lock_guard<std::mutex> lock(impl.placed_mutex);
        bool all_kept = true;
        placed_.resize(times_.size());
        for (std::size_t i = 0; i < times_.size(); ++i) {
            for (const auto& [t, triangles] : impl.placed_last)
                if (t == times_[i]) placed_[i] = triangles;
            all_kept = all_kept && placed_[i];
        }
        // Placing costs a triangle per moving triangle and time; a test without it costs one per candidate.
        if (!all_kept && times.size() * 4 < impl.moving.size() * times_.size()) {
            times_.clear();
            placed_.clear();
            return;
        }
        for (std::size_t i = 0; i < times_.size(); ++i)
            if (!placed_[i]) {
                auto triangles = std::make_shared<std::vector<Triangle>>();
                raycls::place_moving(impl.context, times_[i], *triangles);
                placed_[i] = std::move(triangles);
            }
        impl.placed_last.clear();
        impl.placed_bytes = 0;
        for (std::size_t i = 0; i < times_.size(); ++i) {
            impl.placed_last.emplace_back(times_[i], placed_[i]);
            impl.placed_bytes += placed_[i]->capacity() * sizeof(Triangle);
        }
    }
    const Triangle* at(float t) const {
        for (std::size_t i = 0; i < times_.size(); ++i)
            if (times_[i] == t) return placed_[i]->data();
        return nullptr;
    }

private:
    std::vector<float> times_;
    std::vector<std::shared_ptr<const std::vector<Triangle>>> placed_;
};

// Where one call's rays go in the moving part: the 5D tree of the ray's bin, or, when the call's rays
// share an end or start point, that bin's light buffer around it. Per thread (the bin of the last
// ray and its tree kept).
class MovingPlan {
public:
    MovingPlan(const SpaceTimeClassification::Impl& impl, std::span<const Ray> rays, bool occlusion) : impl_(impl) {
        if (impl.settings.space.light_buffers)
            shared_ = raycls::find_shared_point(rays, occlusion, impl.shared_point_size, kMinLightBufferRays);
    }
    struct Place {
        const raycls::MovingBin* bin = nullptr;
        const raycls::MovingTree* tree = nullptr;
        raycls::Frame frame = raycls::Frame::space;
    };
    void find(float time, Place& place) const {
        const raycls::MovingBin& bin = impl_.bin(impl_.bin_of(time));
        if (place.bin == &bin) return;
        place.bin = &bin;
        place.tree = shared_.frame == raycls::Frame::space
                         ? &bin.space_tree()
                         : &bin.light_buffer(shared_.points, impl_.apex_margin);
        place.frame = place.tree->split_origins ? raycls::Frame::space : shared_.frame;
    }

private:
    static constexpr std::size_t kMinLightBufferRays = 64;
    const SpaceTimeClassification::Impl& impl_;
    raycls::SharedPoint shared_;
};

}  // namespace

SpaceTimeClassification::SpaceTimeClassification(const AnimatedScene& scene, const SpaceTimeSettings& settings,
                                                 const KdBuildRules& rules)
    : impl_(std::make_shared<Impl>(scene, settings, rules)) {}

namespace {

// The moving part of a call: each ray's moving candidates at its time. Closest hit (out: Hit, the
// static hit as the bound) or occlusion (out: 0 / 1, only for the rays the static part left
// unoccluded).
template <bool kOcclusion, class Out>
void moving_part(const SpaceTimeClassification::Impl& impl, std::span<const Ray> rays, std::span<const float> times,
                 std::span<Out> out, const QueryOptions& options) {
    if (impl.moving.empty()) return;
    impl.start_call();
    std::shared_lock<std::shared_mutex> use(impl.use_mutex);
    const PlacedTimes placed(impl, times);
    const MovingPlan plan(impl, rays, kOcclusion);
    run_query(rays.size(), options, 1024, [&](std::size_t b, std::size_t e, QueryCounters* c) {
        MovingPlan::Place place;
        for (std::size_t i = b; i < e; ++i) {
            if constexpr (kOcclusion)
                if (out[i]) continue;
            plan.find(times[i], place);
            const Triangle* at = placed.at(times[i]);
            const raycls::MovingBin& bin = *place.bin;
            if constexpr (kOcclusion) {
                out[i] = (c ? bin.any<true>(rays[i], times[i], at, c, *place.tree, place.frame)
                            : bin.any<false>(rays[i], times[i], at, nullptr, *place.tree, place.frame))
                             ? 1
                             : 0;
            } else {
                out[i] = c ? bin.closest<true>(rays[i], times[i], at, out[i], c, *place.tree, place.frame)
                           : bin.closest<false>(rays[i], times[i], at, out[i], nullptr, *place.tree, place.frame);
            }
        }
    });
}

// The active lanes of packets side by side, with their times (and the slot of each).
struct PacketLanes {
    std::vector<Ray> rays;
    std::vector<float> times;
    std::vector<std::uint32_t> slots;
    PacketLanes(std::span<const Packet16> packets, std::span<const float> slot_times) {
        std::size_t lanes = 0;  // reserved once: growing the arrays copied them again and again
        for (const Packet16& p : packets) lanes += std::size_t(__builtin_popcount(p.active & 0xFFFFu));
        rays.reserve(lanes);
        times.reserve(lanes);
        slots.reserve(lanes);
        for (std::size_t p = 0; p < packets.size(); ++p)
            for (std::uint32_t m = packets[p].active & 0xFFFFu; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                rays.push_back(packets[p].ray(i));
                times.push_back(slot_times[p * 16 + std::size_t(i)]);
                slots.push_back(std::uint32_t(p * 16 + std::size_t(i)));
            }
    }
};

void check_packet_times(const char* what, std::size_t packets, std::span<const float> slot_times,
                        std::span<const Packet16> lanes_of) {
    if (slot_times.size() != packets * 16)
        throw Error(std::string(what) + ": " + std::to_string(slot_times.size()) + " slot times for " +
                    std::to_string(packets) + " packets (16 each)");
    for (std::size_t p = 0; p < packets; ++p)
        for (std::uint32_t m = lanes_of[p].active & 0xFFFFu; m; m &= m - 1) {
            const std::size_t slot = p * 16 + std::size_t(__builtin_ctz(m));
            if (!std::isfinite(slot_times[slot]))
                throw Error(std::string(what) + ": slot " + std::to_string(slot) + " has a time that is not finite");
        }
}

}  // namespace

void SpaceTimeClassification::intersect(std::span<const Ray> rays, std::span<const float> times, std::span<Hit> hits,
                                        const QueryOptions& options) const {
    check_query("SpaceTimeClassification::intersect", rays.size(), hits.size(), options);
    check_times("SpaceTimeClassification::intersect", rays.size(), times);
    impl_->still.intersect(rays, hits, options);
    moving_part<false>(*impl_, rays, times, hits, options);
}

void SpaceTimeClassification::occluded(std::span<const Ray> rays, std::span<const float> times,
                                       std::span<std::uint8_t> occluded, const QueryOptions& options) const {
    check_query("SpaceTimeClassification::occluded", rays.size(), occluded.size(), options);
    check_times("SpaceTimeClassification::occluded", rays.size(), times);
    impl_->still.occluded(rays, occluded, options);
    moving_part<true>(*impl_, rays, times, occluded, options);
}

void SpaceTimeClassification::intersect(std::span<const Packet16> packets, std::span<const float> slot_times,
                                        std::span<PacketHits16> hits, const QueryOptions& options) const {
    check_query("SpaceTimeClassification::intersect", packets.size(), hits.size(), options);
    check_packet_times("SpaceTimeClassification::intersect", packets.size(), slot_times, packets);
    if (impl_->settings.static_packets)
        impl_->still.kd_tree().intersect(packets, hits, options);
    else
        impl_->still.intersect(packets, hits, options);
    if (impl_->moving.empty()) return;
    const PacketLanes lanes(packets, slot_times);
    std::vector<Hit> best(lanes.rays.size());
    for (std::size_t k = 0; k < best.size(); ++k) best[k] = hits[lanes.slots[k] / 16].hit(int(lanes.slots[k] % 16));
    moving_part<false>(*impl_, lanes.rays, lanes.times, std::span<Hit>(best), options);
    for (std::size_t k = 0; k < best.size(); ++k) hits[lanes.slots[k] / 16].set_hit(int(lanes.slots[k] % 16), best[k]);
}

void SpaceTimeClassification::occluded(std::span<const Packet16> packets, std::span<const float> slot_times,
                                       std::span<std::uint32_t> occluded, const QueryOptions& options) const {
    check_query("SpaceTimeClassification::occluded", packets.size(), occluded.size(), options);
    check_packet_times("SpaceTimeClassification::occluded", packets.size(), slot_times, packets);
    if (impl_->settings.static_packets) {
        // Shadow packets reversed towards their light where they can be (MLRTA section 6, as the
        // stream tracer does): the lanes then share an origin and go together through interval
        // traversal instead of one by one. The same segments, so the same occlusion.
        // Reversed a block at a time and traced at once, on the call's threads: one pass over the
        // packets, no copy of all of them.
        const KdTree& kd = impl_->still.kd_tree();
        const double tolerance = mlrta::reversal_tolerance(kd.scene().bounds());
        run_query(packets.size(), options, 256, [&](std::size_t b, std::size_t e, QueryCounters* c) {
            constexpr std::size_t kBlock = 64;
            std::vector<Packet16> traced(std::min(kBlock, e - b));
            for (std::size_t p0 = b; p0 < e; p0 += kBlock) {
                const std::size_t n = std::min(kBlock, e - p0);
                for (std::size_t k = 0; k < n; ++k)
                    if (!mlrta::reverse_for_occlusion(packets[p0 + k], tolerance, traced[k])) traced[k] = packets[p0 + k];
                kd.occluded(std::span<const Packet16>(traced.data(), n), occluded.subspan(p0, n), QueryOptions{1, c});
            }
        });
    } else {
        impl_->still.occluded(packets, occluded, options);
    }
    if (impl_->moving.empty()) return;
    const PacketLanes lanes(packets, slot_times);
    std::vector<std::uint8_t> any(lanes.rays.size());
    for (std::size_t k = 0; k < any.size(); ++k) any[k] = (occluded[lanes.slots[k] / 16] >> (lanes.slots[k] % 16)) & 1u;
    moving_part<true>(*impl_, lanes.rays, lanes.times, std::span<std::uint8_t>(any), options);
    for (std::size_t k = 0; k < any.size(); ++k)
        if (any[k]) occluded[lanes.slots[k] / 16] |= 1u << (lanes.slots[k] % 16);
}

Hit SpaceTimeClassification::intersect(const Ray& ray, float time) const {
    Hit h;
    intersect(std::span<const Ray>(&ray, 1), std::span<const float>(&time, 1), std::span<Hit>(&h, 1));
    return h;
}

bool SpaceTimeClassification::occluded(const Ray& ray, float time) const {
    std::uint8_t o = 0;
    occluded(std::span<const Ray>(&ray, 1), std::span<const float>(&time, 1), std::span<std::uint8_t>(&o, 1));
    return o != 0;
}

void SpaceTimeClassification::clear() const {
    impl_->still.clear();
    std::unique_lock<std::shared_mutex> alone(impl_->use_mutex);
    impl_->free_bins(~std::uint64_t(0));
    impl_->context.peak_bytes = impl_->context.bytes.load();
    std::lock_guard<std::mutex> lock(impl_->placed_mutex);
    impl_->placed_last.clear();
    impl_->placed_bytes = 0;
}

const AnimatedScene& SpaceTimeClassification::scene() const { return impl_->scene; }
const RayClassification& SpaceTimeClassification::static_part() const { return impl_->still; }
const SpaceTimeSettings& SpaceTimeClassification::settings() const { return impl_->settings; }

SpaceTimeStats SpaceTimeClassification::stats() const {
    SpaceTimeStats s;
    s.static_part = impl_->still.stats();
    s.moving_triangles = impl_->moving.size();
    s.time_bins = impl_->bins;
    s.bins_made = impl_->bins_made.load();
    s.bins_freed = impl_->bins_freed.load();
    s.bins_resident = s.bins_made - s.bins_freed;
    s.moving_cells = impl_->context.cells.load();
    s.moving_entries = impl_->context.entries.load();
    {
        std::lock_guard<std::mutex> lock(impl_->placed_mutex);
        s.moving_memory_bytes = impl_->context.bytes.load() + impl_->placed_bytes;
    }
    s.moving_memory_peak_bytes = impl_->context.peak_bytes.load();
    return s;
}

}  // namespace beamtrace
