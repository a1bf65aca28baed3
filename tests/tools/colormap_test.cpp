// The heat map and the normal colours.
#include "report/colormap.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace beamtrace::report {
namespace {

double luma(Rgb8 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

TEST(Colormap, HeatEndpointsClampingAndNaN) {
    EXPECT_EQ(heat_color(0.0), (Rgb8{68, 1, 84}));
    EXPECT_EQ(heat_color(1.0), (Rgb8{253, 231, 37}));
    EXPECT_EQ(heat_color(-3.0), heat_color(0.0));
    EXPECT_EQ(heat_color(7.0), heat_color(1.0));
    EXPECT_EQ(heat_color(std::numeric_limits<double>::quiet_NaN()), heat_color(0.0));
    EXPECT_EQ(heat_color(5.0, 0.0, 10.0), heat_color(0.5));
    EXPECT_EQ(heat_color(5.0, 3.0, 3.0), heat_color(0.0));
}

TEST(Colormap, HeatLightnessRisesSteadily) {
    double previous = -1.0;
    for (int i = 0; i <= 1000; ++i) {
        const double l = luma(heat_color(i / 1000.0));
        EXPECT_GE(l, previous - 0.5) << i;  // rounding to bytes may wobble by a fraction
        previous = l;
    }
    EXPECT_GT(luma(heat_color(1.0)) - luma(heat_color(0.0)), 180.0);
}

TEST(Colormap, NormalColours) {
    EXPECT_EQ(normal_color({0, 0, 1}), (Rgb8{128, 128, 255}));
    EXPECT_EQ(normal_color({0, 0, -5}), (Rgb8{128, 128, 0}));
    EXPECT_EQ(normal_color({3, 0, 0}), (Rgb8{255, 128, 128}));
    EXPECT_EQ(normal_color({0, 0, 0}), (Rgb8{128, 128, 128}));
    EXPECT_EQ(normal_color({std::numeric_limits<float>::infinity(), 0, 0}), (Rgb8{128, 128, 128}));
}

}  // namespace
}  // namespace beamtrace::report
