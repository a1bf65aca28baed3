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

#include "beamtrace/kdtree.hpp"
#include "beamtrace/ray.hpp"

namespace beamtrace {

enum class FrustumTest {
    inverse,  // the paper's inverse culling: cell planes against the beam's rectangles (default)
    direct,   // Assarsson-Moller 4-plane n-vertex test (beams with one origin; others use inverse)
};

enum class EpSearch {
    // The paper's steps 1-3: depth first to the first potential leaf, stacking bifurcations, then
    // the stack popped deepest first, each node's other subtree searched for a potential leaf.
    bifurcation_stack,
    // The same entry point found top down: the first node whose both subtrees hold potential leaves
    // (or the first potential leaf), without searching below the deeper bifurcations (default).
    top_down,
};

struct MlrtaSettings {
    int initial_tile = 128;  // ITS, pixels (a multiple of 4)
    int split_factor = 16;   // SF: 4 (2x2) or 16 (4x4) sub-tiles
    int min_tile = 4;        // MTS, pixels (a multiple of 4): tiles this small go to XP search
    FrustumTest frustum_test = FrustumTest::inverse;
    EpSearch ep_search = EpSearch::top_down;
    // Stop splitting a tile whose entry point is the same as its parent's (not in the paper, which
    // splits down to the minimum size unless the entry point is a leaf).
    bool stop_when_stuck = true;
    // With stop_when_stuck: a tile whose entry point is its parent's is still split once, unless it
    // is itself a part of such a tile or its parts would be single packets (not in the paper). On
    // by default: the parts of a stuck tile often find deeper entry points (docs/mlrta.md).
    bool retry_stuck = true;
    // In leaves, skip triangles outside the frustum of a packet whose rays share one origin (camera
    // and shadow packets), decided 16 triangles at a time with SIMD before the 16-ray tests. Packets
    // with several origins are not culled per triangle. On by default (docs/mlrta.md has numbers).
    bool triangle_culling = true;
    // In entry-point searches of beams with one origin, look at the triangles of a leaf: a leaf whose
    // triangles all lie outside the beam's frustum has no potential intersection, and a leaf with a
    // triangle that every ray of the beam hits inside the leaf ends the search there (termination
    // (4) of the paper, first case). On by default; off leaves only the leaf-box test (2) and
    // completely covered flat leaves.
    bool ep_triangles = true;
    // A sub-tile's entry-point search starts where its parent's search found its first potential
    // leaf (every leaf before it is empty for the parent's beam, so for the sub-tile's), deciding
    // again only the bifurcations on that leaf's path, and a tile's packets start interval
    // traversal at the first potential leaf of its own search (not in the paper; the same answers).
    // On by default; off, searches and traversals start at the entry point, as in the paper.
    bool ep_resume = true;
    // Throws beamtrace::Error naming the bad setting.
    void validate() const;
};

// Work counters (only gathered when asked for; the plain calls count nothing).
struct MlrtaCounters {
    std::uint64_t packets = 0;          // 4x4 packets traced
    std::uint64_t ep_steps = 0;         // nodes visited by entry-point searches
    std::uint64_t xp_steps = 0;         // nodes visited by interval traversal
    std::uint64_t triangle_tests = 0;   // packet/triangle tests not culled
    std::uint64_t tiles = 0;            // tiles whose packets went to XP search (after splitting)
    std::uint64_t divergent_tiles = 0;  // tiles whose rays diverge in sign
    std::uint64_t single_rays = 0;      // rays with a zero direction component, traced alone
    std::uint64_t blocked_tiles = 0;    // occlusion tiles one triangle blocks entirely (no XP search)
    MlrtaCounters& operator+=(const MlrtaCounters& o);
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

class Mlrta {
public:
    // The tree must outlive nothing: Mlrta keeps a copy of the tree handle.
    explicit Mlrta(const KdTree& tree, const MlrtaSettings& settings = {});

    // Closest hits of every active ray of the grid (hits[i] for packets[i]); threads > 1 runs
    // tiles in parallel (TBB). counters / observer may be null / empty.
    void intersect(const PacketGrid& grid, PacketHits16* hits, int threads = 1, MlrtaCounters* counters = nullptr,
                   const TileObserver& observer = {}) const;
    // Occlusion: bit i of occluded[p] set when ray i of packet p hits something in [tnear, tfar].
    void occluded(const PacketGrid& grid, std::uint32_t* occluded, int threads = 1,
                  MlrtaCounters* counters = nullptr) const;

    // One packet by interval traversal from the root (no beam, no entry point): the "no MLRT" path.
    void intersect_packet(const Packet16& packet, PacketHits16& hits, MlrtaCounters* counters = nullptr) const;
    std::uint32_t occluded_packet(const Packet16& packet, MlrtaCounters* counters = nullptr) const;

    const MlrtaSettings& settings() const;
    const KdTree& tree() const;
    std::size_t memory_bytes() const;  // MLRTA's own tables (subtree sizes, covered-leaf flags)

    struct Impl;

private:
    std::shared_ptr<const Impl> impl_;
};

// The same segment traced from its far end: origin org + tfar * dir, direction -dir, interval
// [0, tfar - tnear]. Shadow rays that end at a point light become a beam with a common origin.
Ray reversed(const Ray& ray);

// Shadow rays towards a point light, traced from the light (section 6): when every active ray of
// the packet aims at one point, the light (org + dir, with tnear < 1 and tfar <= 1: a shadow ray
// with direction light - origin), writes each one to `out` as the same segment from that point:
// origin exactly the light (bit for bit, so the packet has one origin), direction start - light,
// parameters [(1 - tfar) / (1 - tnear), 1]. Inactive lanes are copied. Returns false and leaves
// `out` alone when a ray aims elsewhere, or when rounding could move an end of a segment by more
// than `tolerance` (far from the world origin, say). Every check is in float, with bounds on the
// rounding.
bool reverse_towards_light(const Packet16& packet, float tolerance, Packet16& out);

}  // namespace beamtrace
