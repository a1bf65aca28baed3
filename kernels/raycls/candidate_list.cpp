// Candidate sets of ray-space cells (candidate_list.hpp).
#include "raycls/candidate_list.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace beamtrace::raycls {

float candidate_key(const Triangle& tri, int face) {
    const int k = face_axis(face);
    if (face_sign(face) > 0) return std::min(std::min(tri.v0[k], tri.v1[k]), tri.v2[k]);
    return -std::max(std::max(tri.v0[k], tri.v1[k]), tri.v2[k]);
}

CandidateList candidates_from_tree(const KdTree::Impl& tree, const CellBeam& beam, int face,
                                   std::vector<std::uint32_t>& scratch) {
    scratch.clear();
    struct Entry {
        std::uint32_t node;
        Box box;
    };
    Entry stack[128];
    int top = 0;
    if (!tree.nodes.empty() && may_meet_box(beam, tree.bounds)) stack[top++] = Entry{0, tree.bounds};
    while (top > 0) {
        const Entry e = stack[--top];
        const KdNode& node = tree.nodes[e.node];
        if (node.is_leaf()) {
            const std::uint32_t* ids = tree.triangle_ids.data() + node.offset();
            scratch.insert(scratch.end(), ids, ids + node.triangle_count());
            continue;
        }
        const int axis = node.axis();
        Box lower = e.box, upper = e.box;
        lower.upper[axis] = node.split;
        upper.lower[axis] = node.split;
        if (may_meet_box(beam, upper)) stack[top++] = Entry{node.upper_child(), upper};
        if (may_meet_box(beam, lower)) stack[top++] = Entry{e.node + 1, lower};
    }
    std::sort(scratch.begin(), scratch.end());
    scratch.erase(std::unique(scratch.begin(), scratch.end()), scratch.end());

    struct Keyed {
        float key;
        std::uint32_t id;
    };
    std::vector<Keyed> kept;
    kept.reserve(scratch.size());
    for (std::uint32_t id : scratch) {
        if (tree.scene.is_degenerate(id)) continue;
        const Triangle& tri = tree.scene.triangle(id);
        if (may_meet_triangle(beam, tri)) kept.push_back(Keyed{candidate_key(tri, face), id});
    }
    std::sort(kept.begin(), kept.end(),
              [](const Keyed& x, const Keyed& y) { return x.key < y.key || (x.key == y.key && x.id < y.id); });
    CandidateList list;
    list.key.reserve(kept.size());
    list.id.reserve(kept.size());
    list.corners.reserve(kept.size());
    for (const Keyed& k : kept) {
        list.key.push_back(k.key);
        list.id.push_back(k.id);
        list.corners.push_back(tree.scene.triangle(k.id));
    }
    return list;
}

CandidateList candidates_from_parent(const CandidateList& parent, const CellBeam& beam) {
    CandidateList list;
    std::vector<std::uint32_t> keep;
    keep.reserve(parent.size());
    for (std::uint32_t i = 0; i < parent.size(); ++i)
        if (may_meet_triangle(beam, parent.corners[i])) keep.push_back(i);
    list.key.reserve(keep.size());
    list.id.reserve(keep.size());
    list.corners.reserve(keep.size());
    for (std::uint32_t i : keep) {
        list.key.push_back(parent.key[i]);
        list.id.push_back(parent.id[i]);
        list.corners.push_back(parent.corners[i]);
    }
    return list;
}

void add_direction_rects(CandidateList& list, const Box& apex, int face, double direction_margin) {
    const int k = face_axis(face), a = face_a(face), b = face_b(face);
    const double s = face_sign(face);
    const double s0 = s > 0 ? double(apex.lower[k]) : -double(apex.upper[k]);  // min of s o_k
    const double s1 = s > 0 ? double(apex.upper[k]) : -double(apex.lower[k]);  // max of s o_k
    list.rect.resize(list.size());
    for (std::size_t i = 0; i < list.size(); ++i) {
        const Triangle& t = list.corners[i];
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
        DirectionRect& r = list.rect[i];
        if (!in_front) {
            r = DirectionRect{-2.0f, 2.0f, -2.0f, 2.0f};
            continue;
        }
        // Rounded outwards to float, padded.
        r.u0 = float(lo[0] - direction_margin - std::fabs(lo[0]) * 1e-6);
        r.u1 = float(hi[0] + direction_margin + std::fabs(hi[0]) * 1e-6);
        r.v0 = float(lo[1] - direction_margin - std::fabs(lo[1]) * 1e-6);
        r.v1 = float(hi[1] + direction_margin + std::fabs(hi[1]) * 1e-6);
    }
}

CandidateList candidates_in_rect(const CandidateList& parent, const CellBounds& cell) {
    CandidateList list;
    std::vector<std::uint32_t> keep;
    keep.reserve(parent.size());
    for (std::uint32_t i = 0; i < parent.size(); ++i) {
        const DirectionRect& r = parent.rect[i];
        if (r.u0 <= cell.u1 && r.u1 >= cell.u0 && r.v0 <= cell.v1 && r.v1 >= cell.v0) keep.push_back(i);
    }
    list.key.reserve(keep.size());
    list.id.reserve(keep.size());
    list.corners.reserve(keep.size());
    list.rect.reserve(keep.size());
    for (std::uint32_t i : keep) {
        list.key.push_back(parent.key[i]);
        list.id.push_back(parent.id[i]);
        list.corners.push_back(parent.corners[i]);
        list.rect.push_back(parent.rect[i]);
    }
    return list;
}

}  // namespace beamtrace::raycls
