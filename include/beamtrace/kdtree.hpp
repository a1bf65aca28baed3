#pragma once
// A kd-tree over a Scene: SAH build with the construction rules of MLRTA (Reshetov et al. 2005,
// section 3.1), closest-hit and occlusion queries of single rays and of 4x4 packets.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "beamtrace/experimental.hpp"
#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"
#include "beamtrace/stats.hpp"

namespace beamtrace {

// How the tree is built. Defaults are documented in docs/kdtree.md.
struct KdBuildRules {
    // Surface-area-heuristic costs of one traversal step and of one triangle test. A test is cheap
    // next to a step here (16 rays a test, or 16 triangles a test for one ray, while every step is a
    // dependent load): 0.15 traces bunny 1.4x faster than 1.5 (docs/kdtree.md, "SAH constants").
    float traversal_cost = 1.0f;
    float intersection_cost = 0.15f;

    // MLRTA rule 1: always cut off an empty cell whose volume is at least this fraction of its parent.
    bool empty_cell_rule = true;
    float empty_cell_min_volume_fraction = 0.10f;

    // MLRTA rule 2: prefer a split plane completely covered by coplanar triangles; those triangles
    // go to the smaller sub-cell (which makes flat, "2D" cells).
    bool flat_cell_rule = true;

    // MLRTA rule 3: no cell whose surface area is below this fraction of the scene box's area.
    bool tiny_cell_rule = true;
    float tiny_cell_min_area_fraction = 1e-7f;

    // Hard limits: 0 = automatic depth (8 + 1.3 log2 N, at most 60).
    int max_depth = 0;
    // Cells with at most this many triangles become leaves without evaluating splits.
    int leaf_triangles = 1;

    // Hybrid build: cells holding more than this many triangle references choose their split among
    // `bins` bin boundaries per axis (and their references' tight bounds) instead of every event;
    // smaller cells are built by the exact O(N log N) sweep. 0 = the exact sweep everywhere.
    int binned_above = 0;
    static constexpr int kMaxBins = 256;
    int bins = 128;

    // Throws beamtrace::Error if a constant is out of range (negative costs, fractions outside [0,1],
    // bins outside [2, kMaxBins]).
    void validate() const;
};

namespace detail {
struct Access;  // the library's own access to the implementation (never part of the API)
}

class KdTree {
public:
    // progress (optional) is called with a fraction in [0,1] from the building thread.
    using Progress = std::function<void(double)>;
    static KdTree build(const Scene& scene, const KdBuildRules& rules = {}, const Progress& progress = {});

    // The query contract (query.hpp). Single rays and spans of rays: single-ray traversal, front to
    // back with early exit. Spans of packets: interval traversal of each 4x4 packet from the root
    // (MLRTA's "no MLRT" path; lanes that do not travel together are traced one by one).
    Hit intersect(const Ray& ray) const;
    bool occluded(const Ray& ray) const;
    void intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options = {}) const;
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded, const QueryOptions& options = {}) const;
    void intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                   const QueryOptions& options = {}) const;
    void occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                  const QueryOptions& options = {}) const;

    // The same tree with other research switches for its packet queries (experimental.hpp).
    KdTree with_experimental(const KdExperimental& experimental) const;
    const KdExperimental& experimental() const { return experimental_; }

    const Scene& scene() const;
    const KdBuildStats& stats() const;
    // Bytes of the tables packet queries use (each leaf's geometry box), 0 until the first packet
    // query (or prepare_packet_queries) makes them.
    std::size_t packet_table_bytes() const;
    // Makes those tables now (the first packet query does otherwise).
    void prepare_packet_queries() const;

    struct Impl;  // opaque

private:
    friend struct detail::Access;
    explicit KdTree(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
    std::shared_ptr<const Impl> impl_;
    KdExperimental experimental_;
};

// Brute force: every triangle against the ray. The reference the kd-tree is tested against.
Hit intersect_brute_force(const Scene& scene, const Ray& ray);
bool occluded_brute_force(const Scene& scene, const Ray& ray);

}  // namespace beamtrace
