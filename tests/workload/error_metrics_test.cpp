// The error measures of `beamtrace trade`: relative hit-distance error and the per-pixel error of
// ambient-occlusion fractions.
#include <gtest/gtest.h>

#include <cmath>

#include "beamtrace/error.hpp"
#include "experiments/error_metrics.hpp"
#include "rays/ray_set.hpp"

using namespace beamtrace;
using namespace beamtrace::workload;

namespace {

Hit hit_at(float t, std::uint32_t triangle = 0) {
    Hit h;
    h.t = t;
    h.triangle = triangle;
    return h;
}

}  // namespace

TEST(RelativeTError, CountsOnlyRaysWhereBothSidesHit) {
    const std::vector<Hit> oracle = {hit_at(2.0f), hit_at(4.0f, 7), Hit{}, hit_at(1.0f), Hit{}};
    const std::vector<Hit> ours = {hit_at(2.0f), hit_at(5.0f, 3), hit_at(9.0f), Hit{}, Hit{}};
    const RelativeTError e = relative_t_error(ours, oracle);
    EXPECT_EQ(e.rays, 2u);          // rays 0 and 1; a hit against a miss is not a distance error
    EXPECT_DOUBLE_EQ(e.max, 0.25);  // |5 - 4| / 4, whatever the triangles
    EXPECT_DOUBLE_EQ(e.mean, 0.125);
}

TEST(RelativeTError, ZeroWithoutCommonHitsAndExactForEqualHits) {
    EXPECT_EQ(relative_t_error({}, {}).rays, 0u);
    const RelativeTError none = relative_t_error({Hit{}, hit_at(1.0f)}, {hit_at(1.0f), Hit{}});
    EXPECT_EQ(none.rays, 0u);
    EXPECT_EQ(none.mean, 0.0);
    EXPECT_EQ(none.max, 0.0);
    const RelativeTError same = relative_t_error({hit_at(3.0f), hit_at(0.5f)}, {hit_at(3.0f), hit_at(0.5f)});
    EXPECT_EQ(same.rays, 2u);
    EXPECT_EQ(same.max, 0.0);
}

TEST(RelativeTError, OracleHitsAtZeroDistanceAreLeftOut) {
    const RelativeTError e = relative_t_error({hit_at(0.1f), hit_at(1.1f)}, {hit_at(0.0f), hit_at(1.0f)});
    EXPECT_EQ(e.rays, 1u);
    EXPECT_NEAR(e.max, 0.1, 1e-6);
}

TEST(RelativeTError, SizesMustMatch) { EXPECT_THROW(relative_t_error({Hit{}}, {}), Error); }

TEST(OcclusionFractionMae, AveragesThePixelsFractionErrors) {
    // Pixel 5: 4 rays, 3 occluded for us, 1 for the oracle -> 0.5. Pixel 2: 2 rays, both agree -> 0.
    // Pixel 9: 1 ray, we miss the occlusion -> 1. Inactive slots are ignored whatever they say.
    const std::vector<std::uint32_t> pixel = {5, 5, 5, 5, 2, 2, 9, kNoPixel, kNoPixel};
    const std::vector<std::uint8_t> ours = {1, 1, 1, 0, 1, 0, 0, 1, 0};
    const std::vector<std::uint8_t> oracle = {1, 0, 0, 0, 1, 0, 1, 0, 1};
    EXPECT_DOUBLE_EQ(occlusion_fraction_mae(pixel, ours, oracle), (0.5 + 0.0 + 1.0) / 3.0);
}

TEST(OcclusionFractionMae, SwappedAnswersWithinAPixelCancel) {
    // The fraction is what a renderer shows: two rays of one pixel trading answers do not change it.
    EXPECT_EQ(occlusion_fraction_mae({0, 0}, {1, 0}, {0, 1}), 0.0);
}

TEST(OcclusionFractionMae, EmptyAndMismatchedInputs) {
    EXPECT_EQ(occlusion_fraction_mae({}, {}, {}), 0.0);
    EXPECT_EQ(occlusion_fraction_mae({kNoPixel}, {1}, {0}), 0.0);
    EXPECT_THROW(occlusion_fraction_mae({0, 1}, {0}, {0, 0}), Error);
}
