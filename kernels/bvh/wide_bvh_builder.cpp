// The wide BVH's build: top down, each node's range split by binned surface area heuristic (centroid
// bins on all three axes), the child of largest area split again until the node has kWidth children
// or every child fits in a leaf; subtrees of large ranges in parallel (TBB); then the nodes laid out
// depth first (a node's first child right after it) and the leaves' corners copied into nine rows.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <new>
#include <string>

#include <tbb/task_group.h>

#include "beamtrace/error.hpp"
#include "bvh/wide_bvh.hpp"

namespace beamtrace::bvh {

void WideBvhSettings::validate() const {
    if (max_leaf_triangles < 1 || max_leaf_triangles > kMaxLeafTriangles)
        throw Error("WideBvhSettings::max_leaf_triangles must be in 1.." + std::to_string(kMaxLeafTriangles) +
                    ", got " + std::to_string(max_leaf_triangles));
    if (bins < 4 || bins > 64) throw Error("WideBvhSettings::bins must be in 4..64, got " + std::to_string(bins));
}

void AlignedDelete::operator()(void* p) const { ::operator delete[](p, std::align_val_t{alignof(WideNode)}); }

namespace {

struct Prim {
    Box box;
    Float3 centre;
    std::uint32_t id;
};

// A child of a node under construction: a range of the primitives, its box, and the subtree built
// for it when it is not a leaf.
struct BuildNode;
struct BuildChild {
    std::uint32_t begin = 0, end = 0;
    int splits = 0;  // binary splits from the root to this range
    Box box;
    std::unique_ptr<BuildNode> node;  // null: a leaf
};
struct BuildNode {
    std::array<BuildChild, kWidth> children;
    int count = 0;
};

Box range_box(const Prim* p, std::uint32_t b, std::uint32_t e) {
    Box box;
    for (std::uint32_t i = b; i < e; ++i) box.extend(p[i].box);
    return box;
}

// After this many binary splits on a path the split is by count (the median along the widest axis of
// the centroids), so that no path is longer than kMaxDepth.
constexpr int kSahSplits = 48;

class Builder {
public:
    Builder(std::vector<Prim>& prims, const WideBvhSettings& s) : p_(prims.data()), s_(s) {}

    // The node over [b, e) (more than a leaf's triangles), `splits` binary splits from the root.
    std::unique_ptr<BuildNode> build(std::uint32_t b, std::uint32_t e, int splits, const Box& box) {
        auto node = std::make_unique<BuildNode>();
        BuildChild& whole = node->children[0];
        whole.begin = b;
        whole.end = e;
        whole.splits = splits;
        whole.box = box;
        node->count = 1;
        for (;;) {
            int pick = -1;
            float best = -1.0f;
            for (int c = 0; c < node->count; ++c) {
                const BuildChild& ch = node->children[std::size_t(c)];
                if (ch.end - ch.begin <= std::uint32_t(s_.max_leaf_triangles)) continue;
                const float a = ch.box.surface_area();
                if (a > best) best = a, pick = c;
            }
            if (pick < 0 || node->count == kWidth) break;
            BuildChild& ch = node->children[std::size_t(pick)];
            const std::uint32_t mid = split(ch.begin, ch.end, ch.splits);
            BuildChild right;
            right.begin = mid;
            right.end = ch.end;
            right.splits = ch.splits + 1;
            right.box = range_box(p_, mid, ch.end);
            ch.end = mid;
            ch.splits += 1;
            ch.box = range_box(p_, ch.begin, mid);
            node->children[std::size_t(node->count++)] = std::move(right);
        }
        tbb::task_group group;
        for (int c = 0; c < node->count; ++c) {
            BuildChild& ch = node->children[std::size_t(c)];
            if (ch.end - ch.begin <= std::uint32_t(s_.max_leaf_triangles)) continue;
            if (ch.end - ch.begin > 8192)
                group.run([this, &ch] { ch.node = build(ch.begin, ch.end, ch.splits, ch.box); });
            else
                ch.node = build(ch.begin, ch.end, ch.splits, ch.box);
        }
        group.wait();
        return node;
    }

private:
    // Partitions [b, e) (more than one primitive) and returns the first index of the right part,
    // strictly inside the range.
    std::uint32_t split(std::uint32_t b, std::uint32_t e, int splits) {
        Box centres;
        for (std::uint32_t i = b; i < e; ++i) centres.extend(p_[i].centre);
        const Float3 ext = centres.extent();
        const int widest = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
        if (ext[widest] > 0.0f && splits < kSahSplits) {
            const std::uint32_t mid = sah_split(b, e, centres);
            if (mid > b && mid < e) return mid;
        }
        // By count: the median along the widest axis (every centroid equal: any half).
        const std::uint32_t mid = b + (e - b) / 2;
        std::nth_element(p_ + b, p_ + mid, p_ + e,
                         [widest](const Prim& x, const Prim& y) { return x.centre[widest] < y.centre[widest]; });
        return mid;
    }

    std::uint32_t sah_split(std::uint32_t b, std::uint32_t e, const Box& centres) {
        const int nb = s_.bins;
        struct Bin {
            Box box;
            std::uint32_t count = 0;
        };
        float best_cost = std::numeric_limits<float>::infinity();
        int best_axis = -1, best_bin = 0;
        float scale[3];
        for (int a = 0; a < 3; ++a) {
            const float ext = centres.upper[a] - centres.lower[a];
            scale[a] = ext > 0.0f ? float(nb) * (1.0f - 1.0f / 4096.0f) / ext : 0.0f;
        }
        const auto bin_of = [&](const Prim& q, int a) {
            const int k = int((q.centre[a] - centres.lower[a]) * scale[a]);
            return std::clamp(k, 0, nb - 1);
        };
        for (int a = 0; a < 3; ++a) {
            if (scale[a] == 0.0f) continue;
            std::array<Bin, 64> bins{};
            for (std::uint32_t i = b; i < e; ++i) {
                Bin& x = bins[std::size_t(bin_of(p_[i], a))];
                x.box.extend(p_[i].box);
                ++x.count;
            }
            // Right-to-left sweep of areas, then left to right with the costs.
            std::array<float, 64> right_cost{};
            Box acc;
            std::uint32_t n = 0;
            for (int k = nb - 1; k > 0; --k) {
                acc.extend(bins[std::size_t(k)].box);
                n += bins[std::size_t(k)].count;
                right_cost[std::size_t(k)] = acc.surface_area() * float(n);
            }
            acc = Box{};
            n = 0;
            for (int k = 0; k < nb - 1; ++k) {
                acc.extend(bins[std::size_t(k)].box);
                n += bins[std::size_t(k)].count;
                const float cost = acc.surface_area() * float(n) + right_cost[std::size_t(k + 1)];
                if (n > 0 && n < e - b && cost < best_cost) best_cost = cost, best_axis = a, best_bin = k;
            }
        }
        if (best_axis < 0) return b;
        const int a = best_axis;
        Prim* mid = std::partition(p_ + b, p_ + e, [&](const Prim& q) { return bin_of(q, a) <= best_bin; });
        return std::uint32_t(mid - p_);
    }

    Prim* p_;
    const WideBvhSettings& s_;
};

}  // namespace

// Lays the built nodes out depth first and fills the leaves' references.
class WideBvhBuilder {
public:
    static std::uint32_t count_nodes(const BuildNode& n, int depth, int& max_depth) {
        max_depth = std::max(max_depth, depth);
        std::uint32_t total = 1;
        for (int c = 0; c < n.count; ++c)
            if (n.children[std::size_t(c)].node)
                total += count_nodes(*n.children[std::size_t(c)].node, depth + 1, max_depth);
        return total;
    }

    static std::uint32_t lay_out(const BuildNode& n, WideNode* nodes, std::uint32_t& next, std::size_t& leaves) {
        const std::uint32_t index = next++;
        if (index > kNodeIndexMask) throw Error("wide BVH: more than " + std::to_string(kNodeIndexMask + 1) + " nodes");
        WideNode& w = nodes[index];
        for (int a = 0; a < 3; ++a)
            for (int c = 0; c < kWidth; ++c) {
                w.lower[a][c] = std::numeric_limits<float>::infinity();
                w.upper[a][c] = -std::numeric_limits<float>::infinity();
            }
        for (int c = 0; c < kWidth; ++c) w.child[c] = kEmpty, w.unused[c] = 0;
        for (int c = 0; c < n.count; ++c) {
            const BuildChild& ch = n.children[std::size_t(c)];
            for (int a = 0; a < 3; ++a) {
                w.lower[a][c] = ch.box.lower[a];
                w.upper[a][c] = ch.box.upper[a];
            }
            if (ch.node) {
                w.child[c] = lay_out(*ch.node, nodes, next, leaves);
            } else {
                w.child[c] = make_leaf(ch.begin, ch.end - ch.begin);
                ++leaves;
            }
        }
        return make_inner(index, n.count);
    }

    // The corner block of every leaf under ref.
    static void fill_rows(WideBvh& b, const Scene& scene, std::uint32_t ref) {
        if (ref == kEmpty) return;
        if (!is_leaf(ref)) {
            for (int c = 0; c < kWidth; ++c) fill_rows(b, scene, b.nodes[node_index(ref)].child[c]);
            return;
        }
        const std::uint32_t first = leaf_first(ref), n = leaf_count(ref);
        float* block = b.rows.data() + 9 * std::size_t(first);
        for (std::uint32_t i = 0; i < n; ++i) {
            const float* v = &scene.triangle(b.triangle_ids[first + i]).v0.x;
            for (std::uint32_t c = 0; c < 9; ++c) block[c * n + i] = v[c];
        }
    }

    static std::shared_ptr<const WideBvh> build(const Scene& scene, const WideBvhSettings& settings) {
        settings.validate();
        const auto start = std::chrono::steady_clock::now();
        std::vector<Prim> prims;
        prims.reserve(scene.triangle_count());
        for (std::uint32_t t = 0; t < scene.triangle_count(); ++t) {
            if (scene.is_degenerate(t)) continue;
            const Triangle& tri = scene.triangle(t);
            Prim q;
            q.box.extend(tri.v0);
            q.box.extend(tri.v1);
            q.box.extend(tri.v2);
            q.centre = q.box.center();
            q.id = t;
            prims.push_back(q);
        }
        if (prims.size() > std::size_t(kFirstMask) - 16)
            throw Error("a wide BVH holds at most " + std::to_string(kFirstMask - 16) + " triangles, the scene has " +
                        std::to_string(prims.size()));
        auto bvh = std::make_shared<WideBvh>();
        const std::uint32_t n = std::uint32_t(prims.size());
        if (n > 0) {
            bvh->bounds = range_box(prims.data(), 0, n);
            float scale = bvh->bounds.diagonal();
            for (int k = 0; k < 3; ++k)
                scale = std::max({scale, std::fabs(bvh->bounds.lower[k]), std::fabs(bvh->bounds.upper[k])});
            bvh->pad = std::ldexp(scale, -20);
            if (n <= std::uint32_t(settings.max_leaf_triangles)) {
                bvh->root = make_leaf(0, n);
                bvh->stats.leaves = 1;
            } else {
                Builder builder(prims, settings);
                const std::unique_ptr<BuildNode> top = builder.build(0, n, 0, bvh->bounds);
                int depth = 0;
                const std::uint32_t count = count_nodes(*top, 1, depth);
                if (depth > WideBvh::kMaxDepth)
                    throw Error("wide BVH deeper than " + std::to_string(WideBvh::kMaxDepth) + " levels");
                bvh->node_storage_.reset(static_cast<WideNode*>(
                    ::operator new[](sizeof(WideNode) * count, std::align_val_t{alignof(WideNode)})));
                std::uint32_t next = 0;
                bvh->root = lay_out(*top, bvh->node_storage_.get(), next, bvh->stats.leaves);
                bvh->nodes = bvh->node_storage_.get();
                bvh->stats.inner_nodes = count;
                bvh->stats.depth = depth;
            }
        }
        bvh->triangle_ids.resize(n);
        for (std::uint32_t k = 0; k < n; ++k) bvh->triangle_ids[k] = prims[k].id;
        bvh->rows.assign(9 * std::size_t(n) + 16, 0.0f);
        fill_rows(*bvh, scene, bvh->root);
        bvh->stats.triangles = n;
        bvh->stats.memory_bytes = bvh->stats.inner_nodes * sizeof(WideNode) +
                                  bvh->triangle_ids.size() * sizeof(std::uint32_t) + bvh->rows.size() * sizeof(float);
        bvh->stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return bvh;
    }
};

std::shared_ptr<const WideBvh> WideBvh::build(const Scene& scene, const WideBvhSettings& settings) {
    return WideBvhBuilder::build(scene, settings);
}

}  // namespace beamtrace::bvh
