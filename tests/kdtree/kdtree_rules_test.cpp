// The MLRTA construction rules (section 3.1) each change the tree as described, and can be switched off.
#include <gtest/gtest.h>

#include "beamtrace/error.hpp"
#include "beamtrace/kdtree.hpp"
#include "kdtree/kd_node.hpp"
#include "test_scenes.hpp"

using namespace beamtrace;

TEST(KdRules, ValidateRejectsBadConstants) {
    KdBuildRules r;
    r.traversal_cost = -1.0f;
    EXPECT_THROW(r.validate(), Error);
    r = KdBuildRules{};
    r.empty_cell_min_volume_fraction = 1.5f;
    EXPECT_THROW(r.validate(), Error);
    r = KdBuildRules{};
    r.max_depth = 100;
    EXPECT_THROW(r.validate(), Error);
    r = KdBuildRules{};
    r.tiny_cell_min_area_fraction = -0.1f;
    try {
        r.validate();
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("tiny_cell_min_area_fraction"), std::string::npos);
    }
}

TEST(KdRules, ValidateRejectsBadBinning) {
    auto message = [](const KdBuildRules& r) {
        try {
            r.validate();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    KdBuildRules r;
    r.binned_above = -1;
    EXPECT_NE(message(r).find("binned_above"), std::string::npos) << message(r);
    r = KdBuildRules{};
    r.bins = 1;
    EXPECT_NE(message(r).find("bins must be in [2, 256], not 1"), std::string::npos) << message(r);
    r.bins = KdBuildRules::kMaxBins + 1;
    EXPECT_NE(message(r).find("bins"), std::string::npos) << message(r);
    r.bins = KdBuildRules::kMaxBins;
    r.binned_above = 1;
    EXPECT_NO_THROW(r.validate());
    EXPECT_THROW(KdTree::build(test::single_plane(2), KdBuildRules{.bins = 0}), Error);
}

TEST(KdRules, EmptyCellRuleCutsOffEmptySpaceFirst) {
    // One small cluster in a corner of a big box: the first splits must cut away empty space.
    test::Soup soup;
    soup.add({0, 0, 0}, {100, 0, 0}, {0, 0.001f, 0});  // stretches the bounds
    soup.add({0, 0, 100}, {0.001f, 0, 100}, {0, 0.001f, 100});
    for (int i = 0; i < 50; ++i) {
        const float x = 90.0f + float(i % 5), y = float(i / 5);
        soup.add({x, y, 50}, {x + 1, y, 50}, {x, y + 1, 51});
    }
    KdBuildRules on, off;
    off.empty_cell_rule = false;
    const KdTree a = KdTree::build(soup.scene(), on), b = KdTree::build(soup.scene(), off);
    EXPECT_GT(a.stats().empty_cell_splits, 0u);
    EXPECT_EQ(b.stats().empty_cell_splits, 0u);
}

TEST(KdRules, FlatCellRuleMakesFlatCells) {
    const Scene s = test::stacked_boxes(100, 3);
    KdBuildRules on, off;
    off.flat_cell_rule = false;
    const KdTree a = KdTree::build(s, on), b = KdTree::build(s, off);
    EXPECT_GT(a.stats().flat_cell_splits, 0u);
    EXPECT_EQ(b.stats().flat_cell_splits, 0u);
    EXPECT_GT(a.stats().flat_leaves, 0u);
}

TEST(KdRules, TinyCellRuleStopsSubdivision) {
    const Scene s = test::random_soup(20000, 4, 0.01f);
    KdBuildRules coarse;
    coarse.tiny_cell_min_area_fraction = 1e-2f;  // cells may not be smaller than 1% of the scene's area
    KdBuildRules off;
    off.tiny_cell_rule = false;
    const KdTree a = KdTree::build(s, coarse), b = KdTree::build(s, off);
    EXPECT_GT(a.stats().tiny_cell_leaves, 0u);
    EXPECT_EQ(b.stats().tiny_cell_leaves, 0u);
    EXPECT_LT(a.stats().nodes, b.stats().nodes);
    EXPECT_GT(a.stats().mean_triangles_per_leaf, b.stats().mean_triangles_per_leaf);
}

// The binned upper levels take rules 1 and 2 too (rule 1 from the references' tight bounds, rule 2
// where references lie in a candidate plane), and the switches still turn them off.
TEST(KdRules, BinnedLevelsKeepRulesOneAndTwo) {
    test::Soup soup;
    soup.add({0, 0, 0}, {100, 0, 0}, {0, 0.001f, 0});
    soup.add({0, 0, 100}, {0.001f, 0, 100}, {0, 0.001f, 100});
    for (int i = 0; i < 200; ++i) {
        const float x = 90.0f + float(i % 5), y = float(i / 5);
        soup.add({x, y, 50}, {x + 1, y, 50}, {x, y + 1, 51});
    }
    KdBuildRules binned;
    binned.binned_above = 8;
    KdBuildRules off = binned;
    off.empty_cell_rule = false;
    const KdTree a = KdTree::build(soup.scene(), binned), b = KdTree::build(soup.scene(), off);
    EXPECT_GT(a.stats().binned_splits, 0u);
    EXPECT_GT(a.stats().empty_cell_splits, 0u);
    EXPECT_EQ(b.stats().empty_cell_splits, 0u);

    const Scene s = test::stacked_boxes(100, 3);
    binned.binned_above = 1;
    off = binned;
    off.flat_cell_rule = false;
    const KdTree c = KdTree::build(s, binned), d = KdTree::build(s, off);
    EXPECT_GT(c.stats().flat_cell_splits, 0u);
    EXPECT_EQ(d.stats().flat_cell_splits, 0u);
}
