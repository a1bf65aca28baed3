// DirectionSet: the set itself (size, unit length, hemisphere, evenness) and the constant-time
// lookup against brute force on millions of directions: random ones, the poles, the rim, and
// directions exactly between two set points.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "beamtrace/error.hpp"
#include "beamtrace/vlf.hpp"

using namespace beamtrace;

namespace {

double dot_d(Float3 a, Float3 b) { return double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z; }

// The largest |cos| between dir and any set direction, by brute force.
double best_abs_cos(const DirectionSet& set, Float3 dir) {
    const double len = std::sqrt(dot_d(dir, dir));
    double best = 0.0;
    for (int i = 0; i < set.size(); ++i) best = std::max(best, std::fabs(dot_d(dir, set.direction(i))) / len);
    return best;
}

// Checks one lookup: its direction is (within float rounding) as near as the brute-force nearest,
// and `reversed` tells the side.
void check_lookup(const DirectionSet& set, Float3 dir, std::uint64_t& checked) {
    const DirectionSet::Nearest n = set.nearest(dir);
    ASSERT_LT(n.index, std::uint32_t(set.size()));
    const double len = std::sqrt(dot_d(dir, dir));
    const double cos = dot_d(dir, set.direction(int(n.index))) / len;
    const double best = best_abs_cos(set, dir);
    ASSERT_GE(std::fabs(cos), best - 2e-6) << "dir " << dir.x << "," << dir.y << "," << dir.z << " got " << n.index;
    ASSERT_EQ(n.reversed, cos < 0.0) << "dir " << dir.x << "," << dir.y << "," << dir.z;
    ++checked;
}

Float3 random_direction(std::mt19937& rng) {
    std::normal_distribution<float> g;
    for (;;) {
        const Float3 d{g(rng), g(rng), g(rng)};
        if (dot(d, d) > 1e-6f) return normalize(d);
    }
}

}  // namespace

TEST(DirectionSet, CountsAre2mSquaredPlusOne) {
    for (int m = 1; m <= 32; ++m) {
        EXPECT_TRUE(DirectionSet::valid_count(2 * m * m + 1)) << m;
        EXPECT_FALSE(DirectionSet::valid_count(2 * m * m + 2)) << m;
    }
    EXPECT_FALSE(DirectionSet::valid_count(0));
    EXPECT_FALSE(DirectionSet::valid_count(512));
    EXPECT_FALSE(DirectionSet::valid_count(2 * 33 * 33 + 1));
    EXPECT_THROW(DirectionSet{514}, Error);
    try {
        DirectionSet bad(100);
        FAIL() << "100 directions accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("513"), std::string::npos) << e.what();
    }
    EXPECT_EQ(DirectionSet().size(), 513);
}

TEST(DirectionSet, UnitDirectionsOverTheUpperHemisphereSpreadEvenly) {
    for (int count : {9, 33, 129, 513, 2049}) {
        const DirectionSet set(count);
        ASSERT_EQ(set.size(), count);
        double min_nn = 10.0, max_nn = 0.0;
        for (int i = 0; i < count; ++i) {
            const Float3 d = set.direction(i);
            EXPECT_NEAR(std::sqrt(dot_d(d, d)), 1.0, 1e-6);
            EXPECT_GE(d.z, 0.0f);
            if (d.z == 0.0f) {
                EXPECT_TRUE(d.y > 0.0f || (d.y == 0.0f && d.x > 0.0f)) << "one of each opposite rim pair";
            }
            double nn = 10.0;  // angle to the nearest other line
            for (int j = 0; j < count; ++j)
                if (j != i) nn = std::min(nn, std::acos(std::min(1.0, std::fabs(dot_d(d, set.direction(j))))));
            EXPECT_GT(nn, 1e-3) << "two directions on one line";
            min_nn = std::min(min_nn, nn);
            max_nn = std::max(max_nn, nn);
        }
        // Even spread: nearest-neighbour angles within a factor of 2.5 of each other, around the
        // spacing of equal-area cells (sqrt(2 pi / l)).
        EXPECT_LT(max_nn / min_nn, 2.5) << count;
        EXPECT_GT(min_nn, 0.4 * std::sqrt(2.0 * M_PI / count)) << count;
        EXPECT_LT(max_nn, 1.6 * std::sqrt(2.0 * M_PI / count)) << count;
        EXPECT_LE(set.candidates_per_lookup(), 8) << count;
        RecordProperty("candidates_per_lookup_" + std::to_string(count), set.candidates_per_lookup());
    }
}

TEST(DirectionSet, LookupMatchesBruteForceOnRandomDirections) {
    for (auto [count, samples] : {std::pair{9, 300000}, {33, 500000}, {129, 500000}, {513, 2000000}, {2049, 200000}}) {
        const DirectionSet set(count);
        std::mt19937 rng(count);
        std::uint64_t checked = 0;
        for (int k = 0; k < samples; ++k) {
            check_lookup(set, random_direction(rng), checked);
            if (HasFatalFailure()) return;
        }
        EXPECT_EQ(checked, std::uint64_t(samples));
    }
}

TEST(DirectionSet, LookupAtPolesRimAndCellEdges) {
    for (int count : {9, 33, 513}) {
        const DirectionSet set(count);
        std::uint64_t checked = 0;
        for (Float3 d : {Float3{0, 0, 1}, Float3{0, 0, -1}, Float3{1, 0, 0}, Float3{-1, 0, 0}, Float3{0, 1, 0},
                         Float3{0, -1, 0}, Float3{1, 1, 0}, Float3{-1, 1, 0}, Float3{1, 1, 1}, Float3{-1, -1, -1}})
            check_lookup(set, d, checked);
        // The rim, densely, and just above and below it.
        for (int k = 0; k < 200000; ++k) {
            const double phi = 2.0 * M_PI * k / 200000.0;
            for (float z : {0.0f, 1e-7f, -1e-7f, 1e-3f, -1e-3f})
                check_lookup(set, Float3{float(std::cos(phi)), float(std::sin(phi)), z}, checked);
            if (HasFatalFailure()) return;
        }
        // Lines of constant u or v of the lookup table's map (cell edges), and the map's folds.
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
        for (int k = 0; k < 200000; ++k) {
            const float u = float(std::round(unit(rng) * 64.0f)) / 64.0f, v = unit(rng) * (1.0f - std::fabs(u));
            const float z = 1.0f - std::fabs(u) - std::fabs(v);
            check_lookup(set, Float3{u, v, z}, checked);
            check_lookup(set, Float3{v, u, -z}, checked);
            if (v != 0.0f || z != 0.0f) check_lookup(set, Float3{0.0f, v, z}, checked);
            if (HasFatalFailure()) return;
        }
        EXPECT_GT(checked, 1000000u);
    }
}

TEST(DirectionSet, LookupHalfwayBetweenTwoDirections) {
    for (int count : {33, 129, 513}) {
        const DirectionSet set(count);
        std::uint64_t checked = 0;
        for (int i = 0; i < count; ++i) {
            const Float3 a = set.direction(i);
            check_lookup(set, a, checked);
            check_lookup(set, a * -1.0f, checked);
            EXPECT_EQ(set.nearest(a).index, std::uint32_t(i));
            EXPECT_FALSE(set.nearest(a).reversed);
            EXPECT_TRUE(set.nearest(a * -1.0f).reversed);
            for (int j = 0; j < count; ++j) {
                if (j == i) continue;
                for (float s : {1.0f, -1.0f}) {  // a line's two directions
                    const Float3 b = set.direction(j) * s;
                    if (dot(a, b) < 0.9f) continue;     // neighbours only
                    check_lookup(set, a + b, checked);  // exactly between (up to float rounding)
                    check_lookup(set, (a + b) * -1.0f, checked);
                }
            }
            if (HasFatalFailure()) return;
        }
        EXPECT_GT(checked, std::uint64_t(4 * count));
    }
}

TEST(DirectionSet, LookupIgnoresLength) {
    const DirectionSet set(513);
    std::mt19937 rng(3);
    for (int k = 0; k < 100000; ++k) {
        const Float3 d = random_direction(rng);
        const auto a = set.nearest(d);
        for (float scale : {0x1p-60f, 0x1p-10f, 0x1p20f, 0x1p60f}) {
            const auto b = set.nearest(d * scale);
            ASSERT_EQ(a.index, b.index);
            ASSERT_EQ(a.reversed, b.reversed);
        }
    }
}
