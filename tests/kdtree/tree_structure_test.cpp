// Properties of the built tree itself, for every builder (test_scenes.hpp): nodes depth first with
// split planes inside their cells, leaves' ranges tiling the reference list, and no triangle
// missing from a leaf whose cell it reaches into (checked by an independent clipping in double
// precision against the cell shrunk by a hair: reaching that box means reaching the open cell).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "common/access.hpp"
#include "kdtree/kd_node.hpp"
#include "test_scenes.hpp"

using namespace beamtrace;

namespace {

struct P {
    double v[3];
};

// True if the triangle has a point inside the box [lo, hi] (Sutherland-Hodgman against its six planes).
bool reaches(const Triangle& tri, const double (&lo)[3], const double (&hi)[3]) {
    std::vector<P> poly = {{{tri.v0.x, tri.v0.y, tri.v0.z}}, {{tri.v1.x, tri.v1.y, tri.v1.z}},
                           {{tri.v2.x, tri.v2.y, tri.v2.z}}};
    for (int axis = 0; axis < 3; ++axis)
        for (double side : {+1.0, -1.0}) {
            const double plane = side > 0 ? lo[axis] : hi[axis];
            std::vector<P> out;
            for (std::size_t i = 0; i < poly.size(); ++i) {
                const P& a = poly[i];
                const P& b = poly[(i + 1) % poly.size()];
                const double da = side * (a.v[axis] - plane), db = side * (b.v[axis] - plane);
                if (da >= 0) out.push_back(a);
                if ((da >= 0) != (db >= 0)) {
                    P p;
                    for (int k = 0; k < 3; ++k) p.v[k] = a.v[k] + da / (da - db) * (b.v[k] - a.v[k]);
                    out.push_back(p);
                }
            }
            poly.swap(out);
            if (poly.empty()) return false;
        }
    return true;
}

struct Walk {
    const KdTree::Impl& tree;
    std::size_t visited = 0, next_reference = 0, checked_leaves = 0;

    void node(std::uint32_t index, const Box& cell) {
        ASSERT_LT(index, tree.nodes.size());
        ++visited;
        const KdNode& n = tree.nodes[index];
        if (n.is_leaf()) return leaf(n, cell);
        const int axis = n.axis();
        ASSERT_GE(n.split, cell.lower[axis]) << "node " << index;
        ASSERT_LE(n.split, cell.upper[axis]) << "node " << index;
        ASSERT_GT(n.upper_child(), index + 1) << "node " << index;
        Box lower = cell, upper = cell;
        lower.upper[axis] = n.split;
        upper.lower[axis] = n.split;
        node(index + 1, lower);
        node(n.upper_child(), upper);
    }

    void leaf(const KdNode& n, const Box& cell) {
        // Leaves take their references in depth-first order, one after the other.
        ASSERT_EQ(n.offset(), next_reference);
        next_reference += n.triangle_count();
        ASSERT_LE(next_reference, tree.triangle_ids.size());
        const auto begin = tree.triangle_ids.begin() + std::ptrdiff_t(n.offset());
        const std::vector<std::uint32_t> ids(begin, begin + std::ptrdiff_t(n.triangle_count()));
        ASSERT_TRUE(std::is_sorted(ids.begin(), ids.end()));
        if (cell.lower.x == cell.upper.x || cell.lower.y == cell.upper.y || cell.lower.z == cell.upper.z) return;
        double lo[3], hi[3];
        for (int k = 0; k < 3; ++k) {
            const double hair = (double(cell.upper[k]) - double(cell.lower[k])) * 1e-5;
            lo[k] = double(cell.lower[k]) + hair;
            hi[k] = double(cell.upper[k]) - hair;
        }
        ++checked_leaves;
        const Scene& scene = tree.scene;
        for (std::uint32_t t = 0; t < scene.triangle_count(); ++t) {
            if (scene.is_degenerate(t) || std::binary_search(ids.begin(), ids.end(), t)) continue;
            const Triangle& tri = scene.triangle(t);
            Box tb;
            tb.extend(tri.v0);
            tb.extend(tri.v1);
            tb.extend(tri.v2);
            bool apart = false;
            for (int k = 0; k < 3; ++k) apart = apart || double(tb.upper[k]) < lo[k] || double(tb.lower[k]) > hi[k];
            if (apart) continue;
            ASSERT_FALSE(reaches(tri, lo, hi)) << "triangle " << t << " reaches into a leaf that lacks it";
        }
    }
};

void expect_well_formed(const KdTree& built) {
    Walk walk{detail::Access::impl(built)};
    walk.node(0, walk.tree.bounds);
    if (::testing::Test::HasFatalFailure()) return;
    EXPECT_EQ(walk.visited, walk.tree.nodes.size());
    EXPECT_EQ(walk.next_reference, walk.tree.triangle_ids.size());
    EXPECT_GT(walk.checked_leaves, 0u);
}

}  // namespace

class KdTreeStructure : public ::testing::TestWithParam<test::BuildCase> {};

TEST_P(KdTreeStructure, RandomSoupIsWellFormed) {
    expect_well_formed(KdTree::build(test::random_soup(2000, 31), GetParam().rules));
}

TEST_P(KdTreeStructure, BoxesOnAGridAreWellFormed) {
    expect_well_formed(KdTree::build(test::stacked_boxes(60, 32), GetParam().rules));
}

TEST_P(KdTreeStructure, LargeTrianglesAreWellFormed) {
    // Triangles a third of the scene wide: most cross many split planes and are clipped again and again.
    expect_well_formed(KdTree::build(test::random_soup(1500, 33, 0.3f), GetParam().rules));
}

INSTANTIATE_TEST_SUITE_P(Builders, KdTreeStructure, ::testing::ValuesIn(test::build_cases()),
                         [](const ::testing::TestParamInfo<test::BuildCase>& info) { return info.param.name; });
