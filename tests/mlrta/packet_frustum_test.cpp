// Packet frustum culling (leaf triangles against a common-origin packet): the SIMD kernels decide
// exactly as the scalar reference, and no triangle any ray of the packet hits is ever culled.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "common/triangle_reference.hpp"
#include "common/watertight_ray.hpp"
#include "kdtree/packet/packet_kernels.hpp"

using namespace beamtrace;
using namespace beamtrace::kdtree;

namespace {

struct Generator {
    std::mt19937 rng;
    explicit Generator(unsigned seed) : rng(seed) {}
    float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }
    int pick(int n) { return int(rng() % unsigned(n)); }
    Float3 point(float r) { return {uniform(-r, r), uniform(-r, r), uniform(-r, r)}; }

    // 16 rays from one origin around a random direction (spread up to ~6 degrees), all in one octant.
    Packet16 packet(float origin_scale) {
        Packet16 p;
        const Float3 origin = point(origin_scale);
        Float3 centre = point(1);
        for (int k = 0; k < 3; ++k)
            if (std::fabs(centre[k]) < 0.2f) centre[k] = centre[k] < 0 ? -0.2f : 0.2f;
        const bool bounded = pick(3) == 0;  // segments that end (the frustum's reach), like shadow rays
        for (int i = 0; i < 16; ++i) {
            Ray r;
            r.org = origin;
            r.dir = centre + point(0.05f);
            if (bounded) r.tfar = uniform(0.5f, 25.0f);
            p.set_ray(i, r);
        }
        p.active = pick(4) == 0 ? std::uint32_t(1 + pick(0xFFFF)) : 0xFFFFu;
        return p;
    }

    // A triangle near the packet: around a point along one of its rays (or behind the origin),
    // shifted sideways by up to 2% or 30% of the distance, corners within 3% of it.
    Triangle triangle_near(const Packet16& p) {
        const Ray r = p.ray(pick(16));
        const float t = pick(8) == 0 ? uniform(-2, 0) : uniform(0.5f, 20);
        const float reach = std::fabs(t);
        const Float3 centre = r.org + r.dir * t + point(pick(2) ? 0.02f : 0.3f) * reach;
        Float3 c[3];
        for (Float3& corner : c) corner = centre + point(0.03f) * reach;
        return {c[0], c[1], c[2]};
    }
};

std::vector<Isa> isas() {
    std::vector<Isa> out;
    for (Isa isa : {Isa::scalar, Isa::sse42, Isa::avx2, Isa::avx512})
        if (isa_available(isa)) out.push_back(isa);
    return out;
}

// Compares a kernel's bits for triangles tris[0 .. n - 1] with the scalar reference, and counts the
// decisions so that a test can check the generator made both kinds.
struct Decisions {
    std::uint64_t culled = 0, decided = 0;

    testing::AssertionResult same(const OneOriginFrustum& f, std::uint32_t bits, const Triangle* tris, int n) {
        if (bits >> n) return testing::AssertionFailure() << "bits past n";
        for (int i = 0; i < n; ++i) {
            const bool expected = f.misses(tris[i]);
            if (((bits >> i) & 1u) != std::uint32_t(expected))
                return testing::AssertionFailure()
                       << "triangle " << i << " of " << n << ": reference says " << expected;
            culled += expected;
            ++decided;
        }
        return testing::AssertionSuccess();
    }
    void expect_both_kinds(Isa isa) const {
        EXPECT_GT(culled, decided / 10) << isa_name(isa) << ": the generator should make many culled triangles";
        EXPECT_LT(culled, decided - decided / 10) << isa_name(isa) << ": and many kept ones";
    }
};

}  // namespace

TEST(MlrtaPacketFrustum, KernelsDecideExactlyAsTheScalarReference) {
    // The kernels load the corners from rows (the tree's layout, CornerRows): the same decisions as
    // the reference, bit for bit, at every start in a list and with the rows' padding read.
    for (Isa isa : isas()) {
        const FrustumCullKernel kernel = beamtrace::simd::select<PacketKernels>(isa).frustum_cull;
        Generator gen(11 + unsigned(isa));
        Decisions decisions;
        for (int iter = 0; iter < 20000; ++iter) {
            const Packet16 p = gen.packet(iter % 3 == 0 ? 1000.0f : 3.0f);
            const OneOriginFrustum f = make_one_origin_frustum(p, p.active);
            ASSERT_TRUE(f.valid);
            std::vector<Triangle> list;
            const int size = 1 + gen.pick(40);
            for (int i = 0; i < size; ++i) list.push_back(gen.triangle_near(p));
            const std::size_t stride = list.size() + 16;
            std::vector<float> at(9 * stride, 0.0f);
            for (std::size_t r = 0; r < list.size(); ++r)
                for (int c = 0; c < 9; ++c) at[std::size_t(c) * stride + r] = (&list[r].v0.x)[c];
            const CornerRows rows{at.data(), stride};
            const std::size_t first = std::size_t(gen.pick(size));
            const int n = std::min(16, 1 + gen.pick(int(list.size() - first)));
            ASSERT_TRUE(decisions.same(f, kernel(f, rows, first, n), list.data() + first, n)) << isa_name(isa);
        }
        decisions.expect_both_kinds(isa);
    }
}

TEST(MlrtaPacketFrustum, NeverCullsATriangleThatARayOfThePacketHits) {
    Generator gen(99);
    std::uint64_t hit_triangles = 0, culled = 0;
    for (int iter = 0; iter < 30000; ++iter) {
        const Packet16 p = gen.packet(iter % 2 == 0 ? 5000.0f : 2.0f);
        const OneOriginFrustum f = make_one_origin_frustum(p, p.active);
        for (int k = 0; k < 8; ++k) {
            // Triangles around one ray's path, small enough to be missed by the others.
            const Ray r = p.ray(__builtin_ctz(p.active));
            const Float3 centre = r.org + r.dir * gen.uniform(0.5f, 50);
            const float size = gen.pick(2) ? 0.01f : 0.3f;
            const Triangle tri{centre + gen.point(size), centre + gen.point(size), centre + gen.point(size)};
            bool any_hit = false;
            for (std::uint32_t b = p.active; b; b &= b - 1) {
                TriangleHit h;
                any_hit = any_hit || intersect_triangle(make_watertight_ray(p.ray(__builtin_ctz(b))), tri, h);
            }
            const bool miss = f.misses(tri);
            culled += miss;
            if (any_hit) {
                ++hit_triangles;
                ASSERT_FALSE(miss) << "a triangle hit by a ray of the packet was culled (iteration " << iter << ")";
            }
        }
    }
    EXPECT_GT(hit_triangles, 10000u);
    EXPECT_GT(culled, 5000u);
}

TEST(MlrtaPacketFrustum, OnlyForPacketsWithOneOrigin) {
    Generator gen(5);
    Packet16 p = gen.packet(1.0f);
    EXPECT_TRUE(make_one_origin_frustum(p, p.active).valid);
    p.org_x[3] += 0.5f;
    EXPECT_FALSE(make_one_origin_frustum(p, 0xFFFFu).valid);
    EXPECT_TRUE(make_one_origin_frustum(p, 0xFFF7u).valid) << "lane 3 is not part of the group";
    EXPECT_FALSE(make_one_origin_frustum(p, 0u).valid);
}
