// The scene API: validation at the edge, the copy, degenerate triangles.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "beamtrace/error.hpp"
#include "beamtrace/scene.hpp"

using namespace beamtrace;

namespace {

template <class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "<no error>";
}

const std::vector<float> kQuad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
const std::vector<std::uint32_t> kQuadIdx = {0, 1, 2, 0, 2, 3};

}  // namespace

TEST(Scene, CopiesCallerArrays) {
    std::vector<float> v = kQuad;
    std::vector<std::uint32_t> idx = kQuadIdx;
    Scene s(v.data(), 4, idx.data(), 2);
    v.assign(v.size(), 99.0f);
    idx.assign(idx.size(), 7u);
    EXPECT_EQ(s.triangle_count(), 2u);
    EXPECT_EQ(s.vertex_count(), 4u);
    EXPECT_EQ(s.triangle(1).v2, (Float3{0, 1, 0}));
    EXPECT_EQ(s.indices()[5], 3u);
    EXPECT_EQ(s.bounds().lower, (Float3{0, 0, 0}));
    EXPECT_EQ(s.bounds().upper, (Float3{1, 1, 0}));
    EXPECT_GT(s.memory_bytes(), 0u);
    Scene copy = s;  // shares the data
    EXPECT_EQ(&copy.triangle(0), &s.triangle(0));
}

TEST(Scene, SpanConstructor) {
    std::vector<Float3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    std::vector<std::uint32_t> idx = {0, 1, 2};
    Scene s(v, idx);
    EXPECT_EQ(s.triangle_count(), 1u);
    std::vector<std::uint32_t> bad = {0, 1};
    EXPECT_NE(error_of([&] { Scene(v, bad); }).find("not a multiple of 3"), std::string::npos);
}

TEST(Scene, RejectsEmpty) {
    EXPECT_NE(error_of([] { Scene(kQuad.data(), 4, kQuadIdx.data(), 0); }).find("empty scene"), std::string::npos);
    EXPECT_NE(error_of([] { Scene(kQuad.data(), 0, kQuadIdx.data(), 2); }).find("no vertices"), std::string::npos);
}

TEST(Scene, RejectsNullPointers) {
    EXPECT_NE(error_of([] { Scene(nullptr, 4, kQuadIdx.data(), 2); }).find("null"), std::string::npos);
    EXPECT_NE(error_of([] { Scene(kQuad.data(), 4, nullptr, 2); }).find("null"), std::string::npos);
}

TEST(Scene, RejectsNaNAndInfinityNamingTheVertex) {
    std::vector<float> v = kQuad;
    v[3 * 2 + 1] = std::numeric_limits<float>::quiet_NaN();
    const std::string e = error_of([&] { Scene(v.data(), 4, kQuadIdx.data(), 2); });
    EXPECT_NE(e.find("vertex 2"), std::string::npos) << e;
    EXPECT_NE(e.find("NaN"), std::string::npos) << e;
    v = kQuad;
    v[3 * 3 + 2] = -std::numeric_limits<float>::infinity();
    const std::string e2 = error_of([&] { Scene(v.data(), 4, kQuadIdx.data(), 2); });
    EXPECT_NE(e2.find("vertex 3"), std::string::npos) << e2;
    EXPECT_NE(e2.find("infinite"), std::string::npos) << e2;
}

TEST(Scene, RejectsIndexOutOfRangeNamingTheTriangle) {
    std::vector<std::uint32_t> idx = kQuadIdx;
    idx[4] = 4;
    const std::string e = error_of([&] { Scene(kQuad.data(), 4, idx.data(), 2); });
    EXPECT_NE(e.find("triangle 1"), std::string::npos) << e;
    EXPECT_NE(e.find("index 4"), std::string::npos) << e;
    idx[4] = 0xFFFFFFFFu;
    EXPECT_NE(error_of([&] { Scene(kQuad.data(), 4, idx.data(), 2); }).find("out of range"), std::string::npos);
}

TEST(Scene, RejectsTooManyTriangles) {
    // The count is checked before any data is read, so the arrays need not be that large.
    const std::string e = error_of([] { Scene(kQuad.data(), 4, kQuadIdx.data(), Scene::kMaxTriangles + 1); });
    EXPECT_NE(e.find("2^31"), std::string::npos) << e;
}

TEST(Scene, CountsDegenerateTriangles) {
    const std::vector<float> v = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0};
    const std::vector<std::uint32_t> idx = {0, 1, 2,   // collinear
                                            0, 0, 3,   // repeated corner
                                            0, 1, 3};  // fine
    Scene s(v.data(), 4, idx.data(), 3);
    EXPECT_EQ(s.degenerate_count(), 2u);
    EXPECT_TRUE(s.is_degenerate(0));
    EXPECT_TRUE(s.is_degenerate(1));
    EXPECT_FALSE(s.is_degenerate(2));
}
