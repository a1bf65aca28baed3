#pragma once
// Research switches: choices that are not in the papers (or that choose between the paper's method
// and a variant of it), kept to measure them side by side (`beamtrace trade`, docs/mlrta.md). The
// defaults are the measured best. Not a stable API: a switch goes when its question is settled.
namespace beamtrace {

// Packet queries of the kd-tree (KdTree::with_experimental).
struct KdExperimental {
    // In leaves, skip triangles outside the frustum of a packet whose rays share one origin (camera
    // and shadow packets), decided 16 triangles at a time with SIMD before the 16-ray tests.
    bool triangle_culling = true;
};

// How an entry-point search visits the tree.
enum class EpSearch {
    // The paper's steps 1-3: depth first to the first potential leaf, stacking bifurcations, then
    // the stack popped deepest first, each node's other subtree searched for a potential leaf.
    bifurcation_stack,
    // The same entry point found top down: the first node whose both subtrees hold potential leaves
    // (or the first potential leaf), without searching below the deeper bifurcations (default).
    top_down,
};

// How a beam culls a cell in an entry-point search.
enum class FrustumTest {
    inverse,  // the paper's inverse culling: cell planes against the beam's rectangles (default)
    direct,   // Assarsson-Moller 4-plane n-vertex test (beams with one origin; others use inverse)
};

// MLRTA (MlrtaSettings::experimental).
struct MlrtaExperimental {
    FrustumTest frustum_test = FrustumTest::inverse;
    EpSearch ep_search = EpSearch::top_down;
    // Stop splitting a tile whose entry point is the same as its parent's (the paper splits down to
    // the minimum size unless the entry point is a leaf).
    bool stop_when_stuck = true;
    // With stop_when_stuck: a tile whose entry point is its parent's is still split once, unless it
    // is itself a part of such a tile or its parts would be single packets (its parts often find
    // deeper entry points).
    bool retry_stuck = true;
    // KdExperimental::triangle_culling, for MLRTA's packets.
    bool triangle_culling = true;
    // In entry-point searches of beams with one origin, look at the triangles of a leaf: a leaf whose
    // triangles all lie outside the beam's frustum has no potential intersection, and a leaf with a
    // triangle that every ray of the beam hits inside the leaf ends the search there (termination
    // (4) of the paper, first case). Off leaves only the leaf-box test (2) and completely covered
    // flat leaves.
    bool ep_triangles = true;
    // A sub-tile's entry-point search starts where its parent's search found its first potential
    // leaf (every leaf before it is empty for the parent's beam, so for the sub-tile's), deciding
    // again only the bifurcations on that leaf's path, and a tile's packets start interval
    // traversal at the first potential leaf of its own search (the same answers). Off: searches and
    // traversals start at the entry point, as in the paper.
    bool ep_resume = true;
    // Interval traversal of a tile's packets in blocks of xp_packets x xp_packets 4x4 packets (1, 2
    // or 4: 16, 64 or 256 rays) that share one interval, one stack and every inner-node step, each
    // leaf still tested packet by packet. 1 is the paper's (4x4 packets). Beyond the paper
    // (docs/mlrta.md, "Packets traced together"): tiles of one packet are traced alone, so it pays
    // with a minimum tile of at least xp_packets packets (MlrtaSettings::min_tile >= 4 *
    // xp_packets; the default 32 with 4).
    int xp_packets = 4;
    // Occlusion packets (shadow rays) through a wide BVH that the engine builds on its first
    // occlusion query (or Mlrta::prepare_occlusion), walked by a whole packet at once (interval
    // bounds of the packet, or of its rays from their far ends back, then each ray's slab test),
    // instead of the kd-tree's tiles of beams: beyond the paper; a BVH's tight boxes let lit shadow
    // rays pass where a kd-tree's cells make them test every triangle they cross (docs/mlrta.md,
    // "Shadow packets through a wide BVH"). Off: the paper's method. The same answers.
    bool shadow_bvh = true;
};

}  // namespace beamtrace
