// Candidate sets of ray-space cells (candidate_list.hpp).
#include "raycls/candidate_list.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "common/radix_sort.hpp"

namespace beamtrace::raycls {

float candidate_key(const Triangle& tri, int face) {
    const int k = face_axis(face);
    if (face_sign(face) > 0) return std::min(std::min(tri.v0[k], tri.v1[k]), tri.v2[k]);
    return -std::max(std::max(tri.v0[k], tri.v1[k]), tri.v2[k]);
}

namespace {

// The calling thread's buffers: the triangles found, and a stamp per triangle of the scene (the
// number of the search that last found it), so a triangle in several leaves is kept once.
struct TreeScratch {
    std::vector<std::uint32_t> found;
    std::vector<std::uint32_t> stamp;
    std::uint32_t search = 0;
    const KdTree::Impl* tree = nullptr;

    void start(const KdTree::Impl& t) {
        found.clear();
        if (tree != &t || stamp.size() != t.scene.triangle_count() || search == ~0u) {
            stamp.assign(t.scene.triangle_count(), 0);
            search = 0;
            tree = &t;
        }
        ++search;
    }
};

thread_local TreeScratch t_scratch;

// Keys as unsigned integers in the floats' order.
inline std::uint32_t ordered_bits(float x) {
    const std::uint32_t b = std::bit_cast<std::uint32_t>(x);
    return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
}

}  // namespace

CandidateList candidates_from_tree(const KdTree::Impl& tree, const CellBeam& beam, int face) {
    TreeScratch& scratch = t_scratch;
    scratch.start(tree);
    struct Entry {
        std::uint32_t node;
        bool inside;  // the node's box lies inside the beam: no test below it can drop anything
        Box box;
    };
    Entry stack[128];
    int top = 0;
    if (!tree.nodes.empty()) {
        const BoxSide side = box_side(beam, tree.bounds);
        if (side != BoxSide::outside) stack[top++] = Entry{0, side == BoxSide::inside, tree.bounds};
    }
    while (top > 0) {
        const Entry e = stack[--top];
        const KdNode& node = tree.nodes[e.node];
        if (node.is_leaf()) {
            const std::uint32_t* ids = tree.triangle_ids.data() + node.offset();
            for (std::uint32_t j = 0; j < node.triangle_count(); ++j) {
                const std::uint32_t id = ids[j];
                if (scratch.stamp[id] == scratch.search) continue;
                scratch.stamp[id] = scratch.search;
                if (!tree.scene.is_degenerate(id) && (e.inside || may_meet_triangle(beam, tree.scene.triangle(id))))
                    scratch.found.push_back(id);
            }
            continue;
        }
        if (e.inside) {
            stack[top++] = Entry{node.upper_child(), true, e.box};
            stack[top++] = Entry{e.node + 1, true, e.box};
            continue;
        }
        const int axis = node.axis();
        Box lower = e.box, upper = e.box;
        lower.upper[axis] = node.split;
        upper.lower[axis] = node.split;
        const BoxSide up = box_side(beam, upper), low = box_side(beam, lower);
        if (up != BoxSide::outside) stack[top++] = Entry{node.upper_child(), up == BoxSide::inside, upper};
        if (low != BoxSide::outside) stack[top++] = Entry{e.node + 1, low == BoxSide::inside, lower};
    }
    // Sorted by key, then id: 64-bit words (key's bits in order above the id).
    std::vector<std::uint64_t> words(scratch.found.size()), spare;
    for (std::size_t i = 0; i < words.size(); ++i) {
        const std::uint32_t id = scratch.found[i];
        words[i] = (std::uint64_t(ordered_bits(candidate_key(tree.scene.triangle(id), face))) << 32) | id;
    }
    if (words.size() > 2048)
        radix_sort(words, spare, 64, [](std::uint64_t w) { return w; }, 1);
    else
        std::sort(words.begin(), words.end());
    CandidateList list;
    list.items.resize(words.size());
    for (std::size_t i = 0; i < words.size(); ++i) {
        const std::uint32_t id = std::uint32_t(words[i]);
        const Triangle& tri = tree.scene.triangle(id);
        list.items[i] = Candidate{tri, candidate_key(tri, face), id};
    }
    return list;
}

CandidateList candidates_from_parent(const CandidateList& parent, const CellBeam& beam) {
    CandidateList list;
    list.items.reserve(parent.size() / 2 + 8);
    for (const Candidate& c : parent.items)
        if (may_meet_triangle(beam, c.corners)) list.items.push_back(c);
    list.items.shrink_to_fit();
    return list;
}

void add_direction_rects(CandidateList& list, const Box& apex, int face, double direction_margin) {
    const int k = face_axis(face), a = face_a(face), b = face_b(face);
    const double s = face_sign(face);
    const double s0 = s > 0 ? double(apex.lower[k]) : -double(apex.upper[k]);  // min of s o_k
    const double s1 = s > 0 ? double(apex.upper[k]) : -double(apex.lower[k]);  // max of s o_k
    list.rect_items.resize(list.items.size());
    for (std::size_t i = 0; i < list.items.size(); ++i) {
        const Triangle& t = list.items[i].corners;
        const Float3* v[3] = {&t.v0, &t.v1, &t.v2};
        double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
        bool in_front = true;
        for (int c = 0; c < 3 && in_front; ++c) {
            const double xk = s * double((*v[c])[k]);
            const double near = xk - s1, far = xk - s0;  // the smallest and largest lambda
            if (!(near > 0.0)) {
                in_front = false;
                break;
            }
            const int axes[2] = {a, b};
            for (int j = 0; j < 2; ++j) {
                const double x = double((*v[c])[axes[j]]);
                // (x - o) / lambda over o in [apex lo, apex hi], lambda in [near, far].
                const double nmin = x - double(apex.upper[axes[j]]), nmax = x - double(apex.lower[axes[j]]);
                lo[j] = std::min(lo[j], nmin >= 0 ? nmin / far : nmin / near);
                hi[j] = std::max(hi[j], nmax >= 0 ? nmax / near : nmax / far);
            }
        }
        RectCandidate& r = list.rect_items[i];
        r.key = list.items[i].key;
        r.id = list.items[i].id;
        if (!in_front) {
            r.rect = DirectionRect{-2.0f, 2.0f, -2.0f, 2.0f};
            continue;
        }
        // Rounded outwards to float, padded.
        r.rect.u0 = float(lo[0] - direction_margin - std::fabs(lo[0]) * 1e-6);
        r.rect.u1 = float(hi[0] + direction_margin + std::fabs(hi[0]) * 1e-6);
        r.rect.v0 = float(lo[1] - direction_margin - std::fabs(lo[1]) * 1e-6);
        r.rect.v1 = float(hi[1] + direction_margin + std::fabs(hi[1]) * 1e-6);
    }
    list.items.clear();
    list.items.shrink_to_fit();
}

}  // namespace beamtrace::raycls
