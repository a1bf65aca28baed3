#pragma once
// Ray classification (Arvo and Kirk 1987; the space-time thesis's 5D form): the space of rays,
// origin box x direction cube face x 2D direction cell, subdivided lazily where rays arrive. Each
// cell is a beam; its candidate set holds the triangles that may meet the beam, sorted along the
// face's axis, so a ray tests its cell's candidates in order and stops at the first that starts
// beyond its closest hit (or, for occlusion, at any hit).
//
// Light buffers (Haines and Greenberg 1986): when every ray of a call ends at one point (shadow rays
// towards a point light) or starts at one (camera rays), the origin dimensions collapse to a tiny
// box around that point and the classification is a direction map around it: only the two direction
// axes are subdivided (4 children a level instead of 32), and shadow rays are classified from the
// light (reversed; every ray is still tested as given, so the answers do not change).
//
// Candidate sets are made through a kd-tree (docs/raycls.md, deviations): a cell's beam (the box of
// origins swept along the cell's directions: at most nine half-spaces, tested with rounding margins)
// collects the kd-tree leaves it meets and keeps the triangles no half-space rejects; a child's set
// filters its parent's. The answers are exact: closest hit = the smallest t, at equal t the smaller
// triangle id (as brute force); occlusion: any hit.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "beamtrace/kdtree.hpp"
#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"

namespace beamtrace {

namespace detail {
struct Access;
}

struct RayClsSettings {
    // Levels of the 5D tree (each halves all five axes: 32 children); the thesis's depth 5.
    int max_depth = 5;
    // Levels of a light buffer (each halves the two direction axes: 4 children; the levels below its
    // tiles are a tile's grid). 0: automatic, from the triangle count (log4 of triangles / 6, plus 2,
    // at least 6, at most 14).
    int light_buffer_max_depth = 0;
    // A cell with at most this many candidates is not subdivided (the thesis's m = 6).
    int min_candidates = 6;
    // A cell of the 5D tree is made once this many rays have reached its place; the rays before
    // are traced by the kd-tree (exact, the same tie rule). Not in the thesis: on scenes of many
    // triangles a 5D cell costs far more to make than a ray saves, so only cells that enough rays
    // share are made (docs/raycls.md). Light buffers make every cell a ray reaches (1).
    int rays_per_new_cell = 16;
    // The lazy build's work, at most this many candidate entries made per ray classified (summed over
    // the calls since the classification was made or cleared; 0: no cap). Beyond it no cell is made
    // and rays whose cell is missing go to the kd-tree, so a scene whose cells cost more than their
    // rays save (the 5D tree on a million triangles) runs at about the kd-tree's speed, not slower.
    int entries_per_ray = 16;
    // Remember the last cell per thread (the thesis's cache) and try it first.
    bool cache = true;
    // Collapse the origin dimensions of calls whose rays share an end point or a start point.
    bool light_buffers = true;
    // Occlusion rays of a light buffer that fall in one grid cell one after another (shadow rays of
    // neighbouring pixels) are tested together, 16 rays a candidate, instead of one by one (beyond the
    // thesis; docs/raycls.md). The same answers.
    bool packet_light_buffers = true;
    // Bytes the lazily made cells may hold (0: unbounded). Within a call, once the cells hold this
    // much no new cell is made: a ray whose cell is missing is traced by the kd-tree instead (exact;
    // counted as QueryCounters::rays). At the start of a call over the budget the least recently used
    // cells are freed (made again when rays reach them) down to half of it.
    std::size_t memory_budget_bytes = std::size_t{2} << 30;

    // Throws beamtrace::Error naming the bad setting.
    void validate() const;
};

struct RayClsStats {
    std::uint64_t cells_created = 0;       // cells made (every level), light buffers' included
    std::uint64_t cells_freed = 0;         // by the memory budget
    std::uint64_t candidate_entries = 0;   // candidates held now, summed over cells
    std::uint64_t light_buffers = 0;       // direction maps around shared points made so far
    std::size_t memory_bytes = 0;          // held now by the cells
    std::size_t memory_peak_bytes = 0;     // the most held at any time
    double lazy_build_seconds = 0.0;       // spent making cells, summed over threads
    int max_depth_reached = 0;
    // Calls (since made or cleared) whose rays mostly fell back to the kd-tree, so that the 5D tree
    // stopped making cells for the rest of the call (incoherent rays; docs/raycls.md).
    std::uint64_t growth_stops = 0;
};

class RayClassification {
public:
    // Builds the kd-tree it makes candidate sets with (its build is in kd_tree().stats()); the cells
    // are made by the queries. Throws beamtrace::Error for bad settings.
    explicit RayClassification(const Scene& scene, const RayClsSettings& settings = {},
                               const KdBuildRules& rules = {});
    // The same over a tree already built (shared, not copied).
    RayClassification(const KdTree& tree, const RayClsSettings& settings = {});

    // The query contract (query.hpp). Span calls look at their rays first: a shared end point or
    // start point selects a light buffer, otherwise the 5D tree. Counters: raycls.* and
    // triangle_tests.
    Hit intersect(const Ray& ray) const;
    bool occluded(const Ray& ray) const;
    void intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options = {}) const;
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded, const QueryOptions& options = {}) const;
    void intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                   const QueryOptions& options = {}) const;
    void occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                  const QueryOptions& options = {}) const;

    // Frees every cell (the next queries make them again): to time the lazy build with the queries.
    // Not safe while another thread queries.
    void clear() const;

    const Scene& scene() const;
    const KdTree& kd_tree() const;
    const RayClsSettings& settings() const;
    RayClsStats stats() const;

    struct Impl;  // opaque

private:
    friend struct detail::Access;
    std::shared_ptr<Impl> impl_;
};

}  // namespace beamtrace
