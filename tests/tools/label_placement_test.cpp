// Placing plot labels: free sides first, no text on other labels, markers or outside the frame.
#include "report/label_placement.hpp"

#include <gtest/gtest.h>

namespace beamtrace::report {
namespace {

LabelGeometry area() {
    LabelGeometry g;
    g.width = 400.0;
    g.height = 200.0;
    return g;
}

TEST(LabelPlacement, AFreeLabelGoesAboveRight) {
    const std::vector<LabelSide> s = place_labels({{100.0, 100.0, 10}}, {}, area());
    ASSERT_EQ(s.size(), 1u);
    EXPECT_EQ(s[0], LabelSide::above_right);
}

TEST(LabelPlacement, TwoLabelsOfOnePlaceTakeDifferentSides) {
    const std::vector<LabelSide> s = place_labels({{100.0, 100.0, 10}, {100.0, 101.0, 10}}, {}, area());
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s[0], LabelSide::above_right);
    EXPECT_NE(s[1], LabelSide::above_right);
}

TEST(LabelPlacement, TextStaysInsideTheFrame) {
    // At the right edge the text goes left; at the top it goes below.
    EXPECT_EQ(place_labels({{395.0, 100.0, 10}}, {}, area())[0], LabelSide::above_left);
    EXPECT_EQ(place_labels({{100.0, 199.0, 10}}, {}, area())[0], LabelSide::below_right);
    EXPECT_EQ(place_labels({{395.0, 199.0, 10}}, {}, area())[0], LabelSide::below_left);
}

TEST(LabelPlacement, MarkersAreAvoided) {
    // A marker just above right of the point pushes the label below.
    EXPECT_EQ(place_labels({{100.0, 100.0, 10}}, {{125.0, 107.0, 0}}, area())[0], LabelSide::below_right);
    EXPECT_TRUE(place_labels({}, {{1.0, 1.0, 0}}, area()).empty());
}

}  // namespace
}  // namespace beamtrace::report
