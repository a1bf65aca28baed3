#pragma once
// Interval traversal of 4x4 packets through the kd-tree (MLRTA section 4.3, the "XP search"): from
// a start node, one interval [t_cell_min, t_cell_max] for the whole packet, the packet's
// [t_plane_min, t_plane_max] per split, near / far / both exactly as the paper's pseudo-code, with a
// stack. At leaves: the slab-pair test (2) against the leaf's geometry box, the per-lane slab test,
// mailboxing, optional frustum culling of the leaf's triangles, then the 16 rays against each
// triangle with the watertight SIMD kernel; early exit when every active ray has a hit nearer than
// the cells left on the stack. The kd-tree's packet queries (kd16) start at the root; MLRTA starts
// a tile's packets at the entry point its beam found.
#include <cstdint>

#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "kdtree/kd_node.hpp"
#include "kdtree/packet/packet_tables.hpp"

namespace beamtrace::kdtree {

// What packet traversal reads: the tree, its packet tables, and whether leaf triangles outside a
// one-origin packet's frustum are skipped before the 16-ray tests.
struct PacketTraversalContext {
    const KdTree::Impl& kd;
    const PacketTables& tables;
    bool triangle_culling = true;
};

// A node of the tree and its cell.
struct NodeBox {
    std::uint32_t node;
    Box box;
};

// A node on a path down the tree and its child the path did not take.
struct Bifurcation {
    NodeBox node;
    NodeBox other;
};

// A later start than the start node, known to lose nothing: `first` is a leaf reached depth first
// from the start node in the order of the direction signs `sign`, every leaf before it holds nothing
// the packet can hit, and path[0 .. count) are the bifurcations on the way (the start node first),
// whose other children are still to be visited. A group of rays with other signs ignores it.
struct TraversalResume {
    int sign[3] = {0, 0, 0};
    NodeBox first{};
    const Bifurcation* path = nullptr;
    int count = 0;
};

// Where a packet's traversal starts.
struct TraversalStart {
    NodeBox at;
    const TraversalResume* resume = nullptr;
};

// The root of the tree as a start.
TraversalStart root_start(const KdTree::Impl& kd);

// A whole packet from `start`: the lanes are grouped by sign octant and each group is traced by
// interval traversal; lanes with a zero direction component, groups of one or two rays, groups whose
// origins lie more than 1% of the scene diagonal apart and groups whose directions spread more than
// about 3 degrees go to the single-ray kd-tree traversal. Closest hits go to *hits (every lane
// written; no hit where none), occlusion bits to *occluded. With kCount, counters->packets,
// packet_steps, triangle_tests and single_rays grow.
template <bool kOcclusion, bool kCount>
void trace_packet(const PacketTraversalContext& c, const Packet16& packet, const TraversalStart& start,
                  PacketHits16* hits, std::uint32_t* occluded, QueryCounters* counters);

// At most this many packets traced as one.
inline constexpr int kMaxTogether = 16;

// Packets packets[0 .. n) (1 <= n <= kMaxTogether; neighbours of an image: a 2x2 block of 4x4
// packets is 8x8 rays) from `start` by one interval traversal: one interval, one stack and one
// inner-node step for all of them, each leaf tested packet by packet (its own bounds, per-lane box
// test, frustum and triangle tests). Beyond the paper (docs/mlrta.md): the inner-node steps are
// shared by n packets instead of one. Only when the packets' valid lanes (but for those with a zero
// direction component, traced alone) share one sign octant and the whole group passes the tests of
// trace_packet's groups (origins together, directions within about 3 degrees); otherwise packet
// by packet with trace_packet (as is a single packet). Outputs and counters as trace_packet's, per
// packet.
template <bool kOcclusion, bool kCount>
void trace_packets_together(const PacketTraversalContext& c, const Packet16* const* packets, int n,
                            const TraversalStart& start, PacketHits16* const* hits, std::uint32_t* const* occluded,
                            QueryCounters* counters);

}  // namespace beamtrace::kdtree
