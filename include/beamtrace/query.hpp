#pragma once
// The query contract every accelerator (KdTree, Mlrta, VisibilityField, Crsh, RayClassification, SortedLists) offers,
// the same six calls:
//
//   Hit  intersect(const Ray&) const;                  bool occluded(const Ray&) const;
//   void intersect(std::span<const Ray>, std::span<Hit>, const QueryOptions& = {}) const;
//   void occluded (std::span<const Ray>, std::span<std::uint8_t>, const QueryOptions& = {}) const;
//   void intersect(std::span<const Packet16>, std::span<PacketHits16>, const QueryOptions& = {}) const;
//   void occluded (std::span<const Packet16>, std::span<std::uint32_t>, const QueryOptions& = {}) const;
//
// - Rays in any order; answers in input order (answer i for ray i, or for packet i: hits of its 16
//   lanes, bit j of the occlusion word set when lane j is occluded). Inactive lanes and rays that
//   describe no segment (ray.hpp) report no hit and are not occluded.
// - Spans of different sizes are rejected with beamtrace::Error, as are threads < 1.
// - The calls are const and thread-safe. QueryOptions::threads > 1 runs the call on that many TBB
//   threads (the library's own); nothing is allocated per call beyond what the call needs.
// - QueryOptions::counters, when given, receives the call's work counts (the counting variant of the
//   same traversal code; the plain call counts nothing and pays nothing for it).
#include <cstdint>

namespace beamtrace {

// Work counters of queries. Each accelerator fills the fields it has; engine-specific ones are in
// the named groups.
struct QueryCounters {
    std::uint64_t rays = 0;            // rays traced one at a time (single-ray traversal)
    std::uint64_t packets = 0;         // 4x4 packets traced
    std::uint64_t inner_steps = 0;     // kd-tree: inner nodes visited by single rays
    std::uint64_t leaves = 0;          // leaves visited by single rays (kd-tree leaves, VLF tile-BSP leaves)
    std::uint64_t packet_steps = 0;    // kd-tree nodes visited by interval traversal of packets (MLRTA's XP)
    std::uint64_t single_rays = 0;     // lanes of packets traced one by one (zero components, incoherent groups)
    std::uint64_t triangle_tests = 0;  // ray/triangle tests (single rays), packet/triangle tests (packets)

    struct Mlrta {
        std::uint64_t ep_steps = 0;         // nodes visited by entry-point searches
        std::uint64_t tiles = 0;            // tiles whose packets went to interval traversal
        std::uint64_t divergent_tiles = 0;  // tiles whose rays diverge in sign
        std::uint64_t blocked_tiles = 0;    // occlusion tiles one triangle blocks entirely
    } mlrta;

    struct Vlf {
        std::uint64_t tiles = 0;    // tiles visited (empty ones included)
        std::uint64_t entries = 0;  // tile entries whose footprint was compared with the ray's
    } vlf;

    struct Stream {
        std::uint64_t rays = 0;               // rays of stream calls (StreamTracer)
        std::uint64_t origin_groups = 0;      // groups of rays with one origin (masked group traversal)
        std::uint64_t origin_group_rays = 0;  // rays in them
        std::uint64_t pencil_packets = 0;     // packets of rays through one shared point (interval traversal)
        std::uint64_t pencil_rays = 0;        // rays in them
        std::uint64_t single_rays = 0;        // rays traced alone (no group)
        std::uint64_t loose_groups = 0;       // groups of sorted neighbours in no group (masked group traversal)
        std::uint64_t loose_group_rays = 0;   // rays in them
        std::uint64_t group_steps = 0;        // inner nodes visited by origin groups
        std::uint64_t group_leaves = 0;       // leaves tested 16 rays at a time by origin groups (fewer lanes: leaves)
        // inner nodes passed without a step: no lane's segment reaches the plane
        std::uint64_t group_unreached_planes = 0;
        // rays of calls ordered by the bucket pass alone (StreamSettings::bucket_order)
        std::uint64_t bucket_ordered_rays = 0;
        std::uint64_t sort_nanoseconds = 0;  // keys, sort, grouping and the answers' scatter, summed over calls
    } stream;

    // CRSH / RAH (crsh.hpp). Levels are indexed from the rays up: level_*[0] is level 1 (nodes of
    // `fanout` rays). The paper's metric is object_sphere_tests + sphere_cone_tests + triangle_tests.
    struct Crsh {
        static constexpr int kMaxLevels = 4;
        std::uint64_t rays = 0;                      // rays in hierarchies (those that describe a segment)
        std::uint64_t nodes[kMaxLevels] = {};        // nodes built per level
        std::uint64_t object_sphere_tests = 0;       // top nodes x object bounding spheres
        std::uint64_t object_sphere_hits = 0;        // of which kept (their triangles become candidates)
        std::uint64_t sphere_cone_tests = 0;         // triangle bounding spheres against nodes, every level
        std::uint64_t level_tests[kMaxLevels] = {};  // of those, per level
        std::uint64_t level_hits[kMaxLevels] = {};   // (node, triangle) pairs kept per level
        std::uint64_t triangle_tests = 0;            // ray/triangle tests of the final stage
        // Wall-clock nanoseconds of the phases of counted calls: keys (bounding points, directions,
        // hashes), the radix sort, the nodes, the traversal with the final tests.
        std::uint64_t key_ns = 0, sort_ns = 0, hierarchy_ns = 0, traversal_ns = 0;
    } crsh;

    // Ray classification (ray_classification.hpp).
    struct RayCls {
        std::uint64_t rays = 0;               // rays classified (those that describe a segment in the scene's box)
        std::uint64_t light_buffer_rays = 0;  // of which through a light buffer
        std::uint64_t cache_hits = 0;         // rays whose cell was the thread's last one
        std::uint64_t descent_steps = 0;      // cells passed on the way down from a face (cache misses)
        std::uint64_t candidates = 0;         // candidates examined (the thesis's bound tests)
        std::uint64_t run_rays = 0;           // occlusion rays tested 16 to a candidate with their grid cell's run
    } raycls;
    // Sorted lists (sorted_lists.hpp, Fournier and Poulin). Rays and triangle tests are counted in
    // the top-level rays and triangle_tests.
    struct Lists {
        std::uint64_t events = 0;          // events treated: taken in ray order, plus those walked on opening a volume
        std::uint64_t walked_events = 0;   // of these, walked on opening a volume (behind the point it was opened at)
        std::uint64_t volumes_opened = 0;  // volumes entered on every axis (their child lists traversed)
        std::uint64_t heap_ops = 0;        // pushes and pops of the list of next events (stale entries included)
    } lists;

    QueryCounters& operator+=(const QueryCounters& o) {
        rays += o.rays;
        packets += o.packets;
        inner_steps += o.inner_steps;
        leaves += o.leaves;
        packet_steps += o.packet_steps;
        single_rays += o.single_rays;
        triangle_tests += o.triangle_tests;
        mlrta.ep_steps += o.mlrta.ep_steps;
        mlrta.tiles += o.mlrta.tiles;
        mlrta.divergent_tiles += o.mlrta.divergent_tiles;
        mlrta.blocked_tiles += o.mlrta.blocked_tiles;
        vlf.tiles += o.vlf.tiles;
        vlf.entries += o.vlf.entries;
        stream.rays += o.stream.rays;
        stream.origin_groups += o.stream.origin_groups;
        stream.origin_group_rays += o.stream.origin_group_rays;
        stream.pencil_packets += o.stream.pencil_packets;
        stream.pencil_rays += o.stream.pencil_rays;
        stream.single_rays += o.stream.single_rays;
        stream.loose_groups += o.stream.loose_groups;
        stream.loose_group_rays += o.stream.loose_group_rays;
        stream.group_steps += o.stream.group_steps;
        stream.group_leaves += o.stream.group_leaves;
        stream.group_unreached_planes += o.stream.group_unreached_planes;
        stream.bucket_ordered_rays += o.stream.bucket_ordered_rays;
        stream.sort_nanoseconds += o.stream.sort_nanoseconds;
        crsh.rays += o.crsh.rays;
        for (int l = 0; l < Crsh::kMaxLevels; ++l) {
            crsh.nodes[l] += o.crsh.nodes[l];
            crsh.level_tests[l] += o.crsh.level_tests[l];
            crsh.level_hits[l] += o.crsh.level_hits[l];
        }
        crsh.object_sphere_tests += o.crsh.object_sphere_tests;
        crsh.object_sphere_hits += o.crsh.object_sphere_hits;
        crsh.sphere_cone_tests += o.crsh.sphere_cone_tests;
        crsh.triangle_tests += o.crsh.triangle_tests;
        crsh.key_ns += o.crsh.key_ns;
        crsh.sort_ns += o.crsh.sort_ns;
        crsh.hierarchy_ns += o.crsh.hierarchy_ns;
        crsh.traversal_ns += o.crsh.traversal_ns;
        raycls.rays += o.raycls.rays;
        raycls.light_buffer_rays += o.raycls.light_buffer_rays;
        raycls.cache_hits += o.raycls.cache_hits;
        raycls.descent_steps += o.raycls.descent_steps;
        raycls.candidates += o.raycls.candidates;
        raycls.run_rays += o.raycls.run_rays;
        lists.events += o.lists.events;
        lists.walked_events += o.lists.walked_events;
        lists.volumes_opened += o.lists.volumes_opened;
        lists.heap_ops += o.lists.heap_ops;
        return *this;
    }
};

struct QueryOptions {
    int threads = 1;                    // TBB threads of the call (>= 1)
    QueryCounters* counters = nullptr;  // work counts of the call are added here when given
};

}  // namespace beamtrace
