// TriangleBoxTree: boxes of runs of consecutive triangles, then of pairs of nodes up to the root.
#include "vlf/build/triangle_box_tree.hpp"

#include <algorithm>
#include <limits>

namespace beamtrace::vlf {

void TriangleBoxTree::build(std::span<const Triangle> triangles, std::span<const std::uint8_t> present) {
    count_ = triangles.size();
    present_ = present.data();
    const std::size_t runs = std::max<std::size_t>(1, (count_ + kLeaf - 1) / kLeaf);
    leaves_ = 1;
    while (leaves_ < runs) leaves_ *= 2;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    nodes_.assign(2 * std::size_t(leaves_), Node{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}});
    for (std::size_t i = 0; i < count_; ++i) {
        if (!present[i]) continue;
        Node& n = nodes_[leaves_ + i / kLeaf];
        for (const Float3& p : {triangles[i].v0, triangles[i].v1, triangles[i].v2})
            for (int k = 0; k < 3; ++k) {
                n.lo[k] = std::min(n.lo[k], p[k]);
                n.hi[k] = std::max(n.hi[k], p[k]);
            }
    }
    for (std::size_t k = leaves_ - 1; k >= 1; --k) {
        const Node &a = nodes_[2 * k], &b = nodes_[2 * k + 1];
        for (int d = 0; d < 3; ++d) {
            nodes_[k].lo[d] = std::min(a.lo[d], b.lo[d]);
            nodes_[k].hi[d] = std::max(a.hi[d], b.hi[d]);
        }
    }
}

}  // namespace beamtrace::vlf
