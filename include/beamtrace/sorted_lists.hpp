#pragma once
// A hierarchy of 1D sorted lists (Fournier and Poulin: "A Ray Tracing Accelerator Based on a
// Hierarchy of 1D Sorted Lists", Graphics Interface 1993): an exact baseline, not a fast engine.
//
// Every triangle has its axis-aligned box. Each box gives two *events* per axis (its lower and upper
// coordinate); a volume keeps the events of its direct children sorted per axis. A ray walks the
// lists in its own order, merged by the parameter t of each event: a child is *entered* when it has
// had its IN event on all three axes before an OUT event on any; an entered triangle is tested, an
// entered volume is *opened* (its children's lists join the merge). The ray stops when the next
// event lies beyond the closest hit. Without the hierarchy (SortedListRules::flat) the root holds
// every triangle: the paper's Table 1, O(triangles) events per ray.
//
// Exact: every triangle whose box the ray enters before the closest hit is tested with the library's
// watertight test, the event parameters carrying a slack that only adds tests (docs/lists.md). The
// answers are brute force's bit for bit (and so the kd-tree's): the smallest t, at equal t the
// smaller triangle id; occlusion: any hit in [tnear, tfar].
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"

namespace beamtrace {

namespace detail {
struct Access;  // the library's own access to the implementation (never part of the API)
}

// How the hierarchy is built (the paper gives no numbers; docs/lists.md has the defaults' reasons).
struct SortedListRules {
    // No hierarchy: one volume (the root) whose children are all the triangles.
    bool flat = false;
    // Resolution per axis of the regular grid laid over a volume to split it (1..16 each; the paper
    // allows different resolutions per axis). Each object goes to the cell holding its box centre;
    // a cell's volume is the union of its objects' boxes (volumes may overlap), empty cells vanish.
    int grid[3] = {2, 2, 2};
    // A volume with at most this many objects is not split (its children are triangles). >= 1.
    int leaf_objects = 4;
    // When every centre falls in one cell, the objects whose box is at least this fraction of the
    // volume's extent on some axis go to the paper's *special cell* (they stay children of the volume
    // itself) and the rest is split again; in (0, 1].
    float special_cell_fraction = 0.5f;

    // Throws beamtrace::Error naming the bad setting.
    void validate() const;
};

struct SortedListStats {
    std::size_t triangles = 0;             // in the scene
    std::size_t degenerate_triangles = 0;  // zero-area triangles: never tested, not in the lists
    std::size_t volumes = 0;               // the root included
    std::size_t events = 0;                // in all lists: 6 per object (triangle or volume, the root excepted)
    int depth = 0;                         // volumes on the longest root-to-leaf path
    double mean_children = 0.0;            // children (triangles and volumes) per volume
    std::size_t special_cells = 0;         // volumes that kept objects in a special cell
    std::size_t memory_bytes = 0;          // events, volumes, triangle copies
    double build_seconds = 0.0;
};

class SortedLists {
public:
    // Builds the hierarchy (or the flat lists). Throws beamtrace::Error for bad rules.
    static SortedLists build(const Scene& scene, const SortedListRules& rules = {});

    // The query contract (query.hpp). Every ray is traced alone (there is no packet path: packets are
    // traced lane by lane); span calls with QueryOptions::threads > 1 split the rays over TBB threads.
    // Counters: rays, triangle_tests and lists.* from the counting variant of the same code.
    Hit intersect(const Ray& ray) const;
    bool occluded(const Ray& ray) const;
    void intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options = {}) const;
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded, const QueryOptions& options = {}) const;
    void intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                   const QueryOptions& options = {}) const;
    void occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                  const QueryOptions& options = {}) const;

    const Scene& scene() const;
    const SortedListRules& rules() const;
    const SortedListStats& stats() const;

    struct Impl;  // opaque

private:
    friend struct detail::Access;
    explicit SortedLists(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
    std::shared_ptr<const Impl> impl_;
};

}  // namespace beamtrace
