#pragma once
// Streams of arbitrary rays (secondary rays in whatever order an integrator made them), traced by
// the kd-tree after hashing and sorting them into coherent groups (after CRSH, Reis et al. 2017, and
// MLRTA section 6; docs/streams.md):
//
//  1. a 32-bit key per ray, tuned by the ray's kind: rays through a point many rays share (a camera,
//     a point light: found by sampling the stream) are keyed by that point and their direction
//     (octahedral code, no seam); every other ray by its origin (Morton code of its cell);
//  2. a radix sort of the keys (linear time), the rays of one origin cell by a hash of their exact
//     origin too (so that each origin's rays come out together); the rays move with their keys
//     (one scatter into buckets that fit the cache, each bucket sorted there), so no ray is read at
//     a random place of the stream;
//  3. groups cut from the sorted order: up to 16 rays through one shared point make a packet, traced
//     by the kd-tree's interval traversal (shadow rays towards a light are traced from the light,
//     MLRTA section 6); up to 16 rays with one origin (ambient occlusion: the rays of one hit point)
//     make a group traced by a masked traversal that shares every step among them and tests their
//     common cells' triangles 16 rays at a time; the rest go ray by ray, in sorted order;
//  4. the answers scattered back to input order.
//
// The answers do not depend on the order of the input (only on each ray): a ray's closest hit is
// the kd-tree's (the same triangle tests; with equal distances, which of two triangles is reported
// may differ), and occlusion is exact.
#include <cstdint>
#include <memory>
#include <span>

#include "beamtrace/kdtree.hpp"
#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"

namespace beamtrace {

namespace bvh {
class WideBvh;
struct WideBvhKernels;
}  // namespace bvh

struct StreamSettings {
    // Sort the rays into groups (false: every ray by the single-ray traversal in input order; the
    // same answers, for measuring what sorting buys).
    bool sort = true;
    // Shared points: a point is shared when at least this fraction of a sample of the stream passes
    // through it (starts there, or ends there); at most kMaxSharedPoints of them.
    float shared_point_fraction = 0.01f;
    int sample_rays = 4096;
    // Groups of fewer rays than this go ray by ray (2 .. 16).
    int min_group_rays = 4;
    // Rays in no group (no shared point, fewer than min_group_rays with their origin: diffuse
    // bounces) go through the masked group traversal 16 sorted neighbours at a time (beyond the
    // papers; docs/streams.md); false: one by one. The same answers.
    bool group_loose_rays = true;
    // Rays traced alone (in no group, loose, or every ray when sort is off) go through a wide BVH (32
    // children a node) the tracer builds over the tree's scene, instead of the kd-tree's single-ray
    // traversal (beyond the papers; docs/streams.md "Single rays through a wide BVH"). Loose rays then
    // go one by one (group_loose_rays is for the kd-tree's traversal). The same answers.
    bool wide_bvh = true;
    // With the wide BVH: a stream whose sample shows no shared point (ambient occlusion, diffuse
    // bounces: no pencils to group) is ordered by one scatter pass only, by the top digit of its keys
    // (the rays' origin cells, up to 12 bits), instead of the whole sort, and every ray goes one by
    // one through the wide BVH (beyond the papers; docs/streams.md "Streams without shared points in
    // buckets"). false: the whole sort, and rays of one origin in groups through the kd-tree. The
    // same answers.
    bool bucket_order = true;
    // With the wide BVH: occlusion pencils (shadow rays to a point light, 16 sorted neighbours a
    // packet) walk the wide BVH a packet at a time (bvh::occluded_packet, MLRTA's shadow packets'
    // walk: docs/mlrta.md) instead of the kd-tree's interval traversal (beyond the papers;
    // docs/streams.md). The same answers.
    bool bvh_pencils = true;

    static constexpr int kMaxSharedPoints = 16;

    // Throws beamtrace::Error for a value out of range.
    void validate() const;
};

class StreamTracer {
public:
    // The tracer shares the tree (a KdTree is a shared handle). Throws beamtrace::Error for settings
    // out of range. Span calls take at most 2^32 - 1 rays (more: beamtrace::Error).
    explicit StreamTracer(const KdTree& tree, const StreamSettings& settings = {});

    // The query contract (query.hpp). Spans of rays: sorted and grouped as above; single rays and
    // packets: the kd-tree's own queries.
    Hit intersect(const Ray& ray) const;
    bool occluded(const Ray& ray) const;
    void intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options = {}) const;
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded, const QueryOptions& options = {}) const;
    void intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                   const QueryOptions& options = {}) const;
    void occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                  const QueryOptions& options = {}) const;

    const KdTree& tree() const { return tree_; }
    const StreamSettings& settings() const { return settings_; }
    // The wide BVH's bytes (nodes, ids, corner rows) and build time; 0 without it.
    std::size_t wide_bvh_bytes() const;
    double wide_bvh_build_seconds() const;

private:
    KdTree tree_;
    StreamSettings settings_;
    std::shared_ptr<const bvh::WideBvh> bvh_;           // settings_.wide_bvh
    const bvh::WideBvhKernels* bvh_kernels_ = nullptr;  // its kernels, of the tree's instruction set
};

// The order a StreamTracer with these settings over a scene with this box traces `rays` in
// (order[k]: the input index of the k-th ray traced), for handing the same order to another tracer.
// closest_hit: the order of intersect(), else of occluded() (rays ending at a shared point are
// grouped for occlusion only). Throws beamtrace::Error when the spans differ in size.
void stream_order(std::span<const Ray> rays, const Box& scene_bounds, bool closest_hit, std::span<std::uint32_t> order,
                  const StreamSettings& settings = {}, const QueryOptions& options = {});

}  // namespace beamtrace
