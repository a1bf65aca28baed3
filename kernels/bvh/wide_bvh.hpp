#pragma once
// A wide bounding volume hierarchy: thirty-two children a node, boxes of the children stored side by side
// (one register of each of the six planes), leaves of at most 16 triangles whose corners are nine
// rows of floats in one block per leaf (the layout TriangleKernels::ray_rows reads). For the single rays no coherent
// structure of the papers serves (diffuse bounces, the stragglers of a sorted stream): beyond every
// paper this project follows, built only when a stream tracer asks for it (docs/wide_bvh.md).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"
#include "simd/dispatch.hpp"
#include "simd/isa.hpp"

namespace beamtrace::bvh {

constexpr int kWidth = 32;

// A child reference: an inner node (its index and how many children it has: kChildrenShift up), a
// leaf (kLeafBit | (count - 1) << kCountShift | first triangle of the BVH order) or kEmpty (a child
// slot with no box: lower +inf, upper -inf). A node's children fill its first slots, so a walk tests
// only the registers that hold them: most nodes near the leaves have 16 children or fewer, one
// AVX-512 register a plane instead of two, and their upper lines are never read.
constexpr std::uint32_t kLeafBit = 0x80000000u;
constexpr int kCountShift = 27;
constexpr std::uint32_t kFirstMask = (1u << kCountShift) - 1u;
constexpr std::uint32_t kEmpty = 0xFFFFFFFFu;
constexpr int kMaxLeafTriangles = 16;
constexpr int kChildrenShift = 25;
constexpr std::uint32_t kNodeIndexMask = (1u << kChildrenShift) - 1u;  // at most 2^25 inner nodes

inline bool is_leaf(std::uint32_t ref) { return (ref & kLeafBit) != 0; }
inline std::uint32_t leaf_count(std::uint32_t ref) { return ((ref >> kCountShift) & 15u) + 1u; }
inline std::uint32_t leaf_first(std::uint32_t ref) { return ref & kFirstMask; }
inline std::uint32_t make_leaf(std::uint32_t first, std::uint32_t count) {
    return kLeafBit | ((count - 1u) << kCountShift) | first;
}
inline std::uint32_t node_index(std::uint32_t ref) { return ref & kNodeIndexMask; }
inline int node_children(std::uint32_t ref) { return int((ref >> kChildrenShift) & 31u) + 1; }
inline std::uint32_t make_inner(std::uint32_t index, int children) {
    return (std::uint32_t(children - 1) << kChildrenShift) | index;
}

// 1 KB, sixteen cache lines: the 32 children's boxes plane by plane (lower x of the 32, then lower y,
// ...: two AVX-512 registers a plane), their references. Thirty-two children, not the usual eight:
// a walk is a chain of dependent steps as long as the levels it goes down, and wider nodes make
// fewer levels (room diffuse bounces 4.7 nodes a ray with 8 children, 3.1 with 16, 2.1 with 32);
// measured faster on this project's AVX-512 machine (docs/streams.md, "Single rays through a wide
// BVH"); not measured on AVX2 or SSE4.2 machines, which test a node in 4 or 8 steps.
struct alignas(64) WideNode {
    float lower[3][kWidth];
    float upper[3][kWidth];
    std::uint32_t child[kWidth];
    std::uint32_t unused[kWidth];
};
static_assert(sizeof(WideNode) == 32 * kWidth);

struct WideBvhSettings {
    // Leaves hold at most this many triangles (1 .. kMaxLeafTriangles); a range is split by binned
    // surface area heuristic until it fits.
    int max_leaf_triangles = 12;
    // Centroid bins per axis (4 .. 64). 32: room's nodes a diffuse ray 3.45 -> 3.07 and leaves 2.51 ->
    // 2.36 against 16 (bunny's the same); 64 no better.
    int bins = 32;

    // Throws beamtrace::Error for a value out of range.
    void validate() const;
};

struct WideBvhStats {
    std::size_t inner_nodes = 0, leaves = 0, triangles = 0;  // triangles: non-degenerate, in leaves
    int depth = 0;                                           // inner levels from the root to the deepest leaf
    double build_seconds = 0;
    std::size_t memory_bytes = 0;  // nodes, ids and corner rows
};

struct AlignedDelete {
    void operator()(void* p) const;
};

class WideBvh {
public:
    // Degenerate triangles (Scene::is_degenerate) are left out: no query can hit them.
    static std::shared_ptr<const WideBvh> build(const Scene& scene, const WideBvhSettings& settings = {});

    // The deepest stack a traversal needs: (kWidth - 1) entries per inner level.
    static constexpr int kMaxDepth = 80;

    std::uint32_t root = kEmpty;              // a child reference (a leaf for a small scene)
    const WideNode* nodes = nullptr;          // nodes[0 .. stats.inner_nodes), by node_index(ref)
    std::vector<std::uint32_t> triangle_ids;  // the BVH order: leaf triangles side by side
    // The corners of each leaf in one block: the leaf of triangles first .. first + n - 1 (BVH order)
    // has its nine rows of n floats (row c: component c % 3 of corner c / 3) at rows + 9 * first,
    // n floats apart, as TriangleKernels::ray_rows reads them (stride n); 16 floats of padding end
    // the array, so every row is readable 16 floats on. A leaf is a few consecutive cache lines.
    std::vector<float> rows;
    Box bounds;        // of the triangles in leaves
    float pad = 0.0f;  // the scene's scale * 2^-20 (kdtree::LaneBoxRays::pad: boxes widened by it)
    WideBvhStats stats;

private:
    std::unique_ptr<WideNode[], AlignedDelete> node_storage_;
    friend class WideBvhBuilder;
};

// Closest hit (kOcclusion false) or any hit of one ray, exactly as the kd-tree's single-ray traversal
// answers (the same watertight test: the same t; at equal t another triangle may be the one found);
// counters (may be null in the plain forms) count rays, inner_steps, leaves and triangle_tests.
struct PacketBounds;

struct WideBvhKernels {
    Isa isa;
    Hit (*intersect)(const WideBvh& bvh, const Ray& ray);
    Hit (*occluded)(const WideBvh& bvh, const Ray& ray);
    Hit (*intersect_counted)(const WideBvh& bvh, const Ray& ray, QueryCounters* counters);
    Hit (*occluded_counted)(const WideBvh& bvh, const Ray& ray, QueryCounters* counters);
    // The children of a node a packet's interval bounds may meet (wide_bvh_packet.hpp;
    // packet_node_reference is the scalar form).
    std::uint32_t (*packet_node)(const PacketBounds& bounds, const WideNode& node, int children);
    // A packet's interval bounds (packet_bounds_reference).
    bool (*packet_bounds)(const Packet16& packet, std::uint32_t lanes, const float* const inv[3], PacketBounds& bounds);
    // The same test on the boxes of a leaf's triangles (packet_leaf_reference).
    std::uint32_t (*packet_leaf)(const PacketBounds& bounds, const float* block, int count);
};

const WideBvhKernels& wide_bvh_kernels(Isa isa);
inline const WideBvhKernels& wide_bvh_kernels() { return wide_bvh_kernels(best_isa()); }

}  // namespace beamtrace::bvh

BEAMTRACE_KERNEL_TABLE(beamtrace::bvh::WideBvhKernels);
