#pragma once
// TriangleBoxTree: which triangles a tile's beam may meet, without rasterising the scene (lazy tile
// builds, parallel_subfield.hpp). The field's triangles lie along a Morton curve (spatial_order.hpp),
// so runs of kLeaf consecutive ones are compact: an implicit binary tree over those runs, each node
// the box of its triangles' corners. A query projects node boxes onto the PSF's canonical (x, y)
// plane (centre and half extents through the rotation: a conservative interval) and reports, in
// ascending order, the triangles of every run whose box meets the given rectangle. Callers decide
// triangle by triangle (TileRasteriser::touches, clip_to_prism), so only conservativeness matters.
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "beamtrace/scene.hpp"
#include "vlf/directions/canonical_frame.hpp"

namespace beamtrace::vlf {

class TriangleBoxTree {
public:
    static constexpr std::uint32_t kLeaf = 8;

    // (Re)computes every box from the triangles' current corners; present[i] == 0 leaves i out.
    void build(std::span<const Triangle> triangles, std::span<const std::uint8_t> present);

    // Calls f(i) for every present triangle i of a run whose projected box meets
    // [x0, x1] x [y0, y1] in the canonical space of frame (relative to the grid's centre).
    template <class F>
    void query(const CanonicalFrame& frame, const Vec3d& centre, double x0, double x1, double y0, double y1,
               F&& f) const {
        if (count_ == 0) return;
        const Vec3d a1{std::fabs(frame.e1.x), std::fabs(frame.e1.y), std::fabs(frame.e1.z)};
        const Vec3d a2{std::fabs(frame.e2.x), std::fabs(frame.e2.y), std::fabs(frame.e2.z)};
        std::uint32_t stack[64];
        int top = 0;
        stack[top++] = 1;
        while (top > 0) {
            const std::uint32_t k = stack[--top];
            const Node& b = nodes_[k];
            if (!(b.lo[0] <= b.hi[0])) continue;  // no present triangle below
            const Vec3d c{0.5 * (double(b.lo[0]) + b.hi[0]) - centre.x, 0.5 * (double(b.lo[1]) + b.hi[1]) - centre.y,
                          0.5 * (double(b.lo[2]) + b.hi[2]) - centre.z};
            const Vec3d e{0.5 * (double(b.hi[0]) - b.lo[0]), 0.5 * (double(b.hi[1]) - b.lo[1]),
                          0.5 * (double(b.hi[2]) - b.lo[2])};
            const double cx = frame.e1.x * c.x + frame.e1.y * c.y + frame.e1.z * c.z;
            const double ex = a1.x * e.x + a1.y * e.y + a1.z * e.z;
            if (cx + ex < x0 || cx - ex > x1) continue;
            const double cy = frame.e2.x * c.x + frame.e2.y * c.y + frame.e2.z * c.z;
            const double ey = a2.x * e.x + a2.y * e.y + a2.z * e.z;
            if (cy + ey < y0 || cy - ey > y1) continue;
            if (k >= leaves_) {
                const std::size_t first = std::size_t(k - leaves_) * kLeaf;
                const std::size_t end = std::min(first + kLeaf, count_);
                for (std::size_t i = first; i < end; ++i)
                    if (present_[i]) f(std::uint32_t(i));
                continue;
            }
            stack[top++] = 2 * k + 1;  // right after left: ascending ids
            stack[top++] = 2 * k;
        }
    }

    std::size_t memory_bytes() const { return nodes_.capacity() * sizeof(Node); }

private:
    struct Node {
        float lo[3], hi[3];
    };
    std::size_t count_ = 0;
    std::uint32_t leaves_ = 1;  // a power of two; node k's children are 2k and 2k + 1, leaf j is leaves_ + j
    std::vector<Node> nodes_;
    const std::uint8_t* present_ = nullptr;
};

}  // namespace beamtrace::vlf
