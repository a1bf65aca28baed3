#pragma once
// MLRTA (Reshetov, Soupikov, Hurley: "Multi-Level Ray Tracing Algorithm", SIGGRAPH 2005) over a
// kd-tree: beams of rays from image tiles find an entry point (EP) deep in the tree with inverse
// frustum culling and a bifurcation stack, tiles split adaptively, and 4x4 packets finish with
// interval traversal (XP) from their tile's entry point. Exact: every closest hit equals the one a
// single ray finds.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>

#include "beamtrace/experimental.hpp"
#include "beamtrace/kdtree.hpp"
#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"

namespace beamtrace {

struct MlrtaSettings {
    int initial_tile = 128;  // ITS, pixels (a multiple of 4)
    int split_factor = 16;   // SF: 4 (2x2) or 16 (4x4) sub-tiles
    int min_tile = 32;       // MTS, pixels (a multiple of 4): tiles this small go to XP search
                             // (the paper's 4; 16 and more let blocks of 4x4 packets go together,
                             // xp_packets; 32 measured fastest: docs/mlrta.md)
    // Choices that are not the paper's, or between the paper's method and a variant (measured in
    // docs/mlrta.md; experimental.hpp).
    MlrtaExperimental experimental;
    // Throws beamtrace::Error naming the bad setting.
    void validate() const;
};

// Packets of an image in row-major order of 4x4 pixel blocks: packet (x, y) = packets[y * columns + x].
struct PacketGrid {
    const Packet16* packets = nullptr;
    int columns = 0, rows = 0;
};

// What happened to one tile: its packets (in packet units), its entry point and the size of the
// subtree below it (the paper's geometric complexity), and whether its rays diverged.
struct TileInfo {
    int x0, y0, x1, y1;
    std::uint32_t entry_node;
    std::size_t subtree_nodes;
    bool divergent;
};
using TileObserver = std::function<void(const TileInfo&)>;

namespace detail {
struct Access;  // the library's own access to the implementation (never part of the API)
}

class Mlrta {
public:
    // Keeps a copy of the tree handle (the tree's nodes are shared, not copied).
    explicit Mlrta(const KdTree& tree, const MlrtaSettings& settings = {});

    // Images: the packets of a grid (PacketGrid above) are traced by tiles of beams: entry-point
    // search, adaptive splitting, interval traversal from the entry points. hits / occluded hold one
    // element per packet of the grid (checked). QueryOptions::threads runs tiles in parallel.
    // occluded() traces shadow rays from their light when they all end at one point (or ray by ray
    // reversed when that is exact: section 6 of the paper; docs/mlrta.md): then every packet's rays
    // share one origin. observer (optional) hears of every tile traced.
    void intersect(const PacketGrid& grid, std::span<PacketHits16> hits, const QueryOptions& options = {},
                   const TileObserver& observer = {}) const;
    void occluded(const PacketGrid& grid, std::span<std::uint32_t> occluded, const QueryOptions& options = {}) const;

    // The query contract (query.hpp) for rays in no image order: packets (and spans of rays, 16 at a
    // time) by interval traversal from the root, occlusion packets reversed towards their light
    // first as above; single rays by the tree's single-ray traversal.
    Hit intersect(const Ray& ray) const;
    bool occluded(const Ray& ray) const;
    void intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options = {}) const;
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded, const QueryOptions& options = {}) const;
    void intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                   const QueryOptions& options = {}) const;
    void occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                  const QueryOptions& options = {}) const;

    const MlrtaSettings& settings() const;
    // Builds now what occlusion queries use (the wide BVH of MlrtaExperimental::shadow_bvh), instead
    // of at the first one; nothing when that is off. Thread-safe; memory_bytes() counts it once built.
    void prepare_occlusion() const;
    const KdTree& tree() const;
    std::size_t memory_bytes()
        const;  // MLRTA's own tables (subtree sizes, covered-leaf flags) and the tree's packet tables

    struct Impl;  // opaque

private:
    friend struct detail::Access;
    std::shared_ptr<const Impl> impl_;
};

}  // namespace beamtrace
