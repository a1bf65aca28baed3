#pragma once
// Ray classification in space-time (the thesis's 6D form), exact on an AnimatedScene: a ray at time t
// gets the answer a static engine built on scene.at(t) gives.
//
// Time is divided only where triangles move: what does not move (AnimatedScene::static_part) is one
// RayClassification, made once and reused by every frame; the moving triangles are classified per
// time bin (the animation's time span cut into equal bins) in a 5D tree of their swept boxes over
// the bin, made lazily where rays arrive. A ray tests its static cell, then its moving cell with each
// candidate placed at the ray's time (AnimatedScene::triangle_at, the one interpolation). Closest
// hit: the smaller t, at equal t the smaller triangle id; occlusion: any hit. Bins no call has used
// for `keep_calls` calls are freed (cells of past frames).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "beamtrace/animated_scene.hpp"
#include "beamtrace/kdtree.hpp"
#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "beamtrace/ray_classification.hpp"

namespace beamtrace {

struct SpaceTimeSettings {
    RayClsSettings space;  // the static part's classification
    // Time bins over [start_time, end_time]. 0: automatic, about one bin per the moving triangles'
    // mean size of motion (mean path of a corner over mean triangle size), at most 1024.
    int time_bins = 0;
    // The moving part's 5D trees: levels (32 children each) and the thesis's m.
    int max_depth = 4;
    int min_candidates = 6;
    // A bin no call used in this many calls is freed at the start of the next.
    int keep_calls = 4;
    // Not the thesis (docs/raycls.md): packet queries trace the static part with the kd-tree's
    // interval traversal of 4x4 packets (kd16's) instead of the static classification, occlusion
    // packets reversed towards their light first where they can be (as MLRTA does); the moving
    // part is classified as ever. Closest hits at equal t may then name another triangle of the tie.
    bool static_packets = false;
    // The static part's kd-tree is built with the KdBuildRules given; when their binned_above is 0
    // it is this instead: binned levels above this many references (docs/kdtree.md; measured on
    // `spin`: the build saves more than the tree's loss costs over 24 frames). 0: the exact sweep.
    int static_binned_above = 4096;

    void validate() const;  // throws beamtrace::Error naming the bad setting
};

struct SpaceTimeStats {
    RayClsStats static_part;
    std::size_t moving_triangles = 0;
    int time_bins = 0;
    std::uint64_t bins_made = 0, bins_freed = 0, bins_resident = 0;
    std::uint64_t moving_cells = 0, moving_entries = 0;
    std::size_t moving_memory_bytes = 0, moving_memory_peak_bytes = 0;
};

class SpaceTimeClassification {
public:
    explicit SpaceTimeClassification(const AnimatedScene& scene, const SpaceTimeSettings& settings = {},
                                     const KdBuildRules& rules = {});

    // times[i] is ray i's time (finite; outside the animation's span the scene is clamped, as
    // AnimatedScene::position does). Throws beamtrace::Error for mismatched sizes or a time that is
    // not finite (naming the ray).
    Hit intersect(const Ray& ray, float time) const;
    bool occluded(const Ray& ray, float time) const;
    void intersect(std::span<const Ray> rays, std::span<const float> times, std::span<Hit> hits,
                   const QueryOptions& options = {}) const;
    void occluded(std::span<const Ray> rays, std::span<const float> times, std::span<std::uint8_t> occluded,
                  const QueryOptions& options = {}) const;
    // 4x4 packets; slot_times[p * 16 + i] is the time of packet p's lane i (16 per packet, inactive
    // lanes' ignored). The static part by packets (the classification's, or the kd-tree's with
    // static_packets), the moving part ray by ray.
    void intersect(std::span<const Packet16> packets, std::span<const float> slot_times,
                   std::span<PacketHits16> hits, const QueryOptions& options = {}) const;
    void occluded(std::span<const Packet16> packets, std::span<const float> slot_times,
                  std::span<std::uint32_t> occluded, const QueryOptions& options = {}) const;

    // Frees every cell and bin. Not safe while another thread queries.
    void clear() const;

    const AnimatedScene& scene() const;
    const RayClassification& static_part() const;
    const SpaceTimeSettings& settings() const;
    SpaceTimeStats stats() const;

    struct Impl;  // opaque

private:
    std::shared_ptr<Impl> impl_;
};

}  // namespace beamtrace
