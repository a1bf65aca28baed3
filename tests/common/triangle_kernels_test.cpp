// Property tests: every SIMD kernel returns, lane by lane and bit for bit, what the scalar
// reference returns, on millions of random cases biased towards edges, corners and zero components.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <random>
#include <vector>

#include "common/triangle_kernels.hpp"
#include "common/triangle_reference.hpp"

using namespace beamtrace;

namespace {

class CaseGenerator {
public:
    explicit CaseGenerator(unsigned seed) : rng_(seed) {}

    float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng_); }
    int pick(int n) { return int(rng_() % unsigned(n)); }

    Float3 point(float r) {
        Float3 p{uniform(-r, r), uniform(-r, r), uniform(-r, r)};
        // Sometimes snap a coordinate to a small set of values so that exact ties and zeros occur.
        for (int a = 0; a < 3; ++a)
            if (pick(6) == 0) p[a] = float(pick(3) - 1);
        return p;
    }

    Triangle triangle() {
        Triangle t{point(2), point(2), point(2)};
        if (pick(20) == 0) t.v2 = t.v1;                      // degenerate
        if (pick(20) == 0) t.v2 = t.v0 + (t.v1 - t.v0) * 2;  // collinear
        return t;
    }

    // A ray aimed at a corner, an edge point or an interior point of tri, or anywhere.
    Ray ray_towards(const Triangle& tri) {
        Float3 target;
        const float a = uniform(0, 1), b = uniform(0, 1);
        switch (pick(5)) {
            case 0:
                target = pick(3) == 0 ? tri.v0 : (pick(2) == 0 ? tri.v1 : tri.v2);
                break;
            case 1:
                target = tri.v0 + (tri.v1 - tri.v0) * a;
                break;
            case 2:
                target = tri.v1 + (tri.v2 - tri.v1) * 0.5f;
                break;
            case 3:
                target = tri.v0 + (tri.v1 - tri.v0) * (a * 0.5f) + (tri.v2 - tri.v0) * (b * 0.5f);
                break;
            default:
                target = point(2);
                break;
        }
        Ray r;
        r.org = point(4);
        r.dir = target - r.org;
        for (int k = 0; k < 3; ++k) {
            if (pick(12) == 0) r.dir[k] = pick(2) ? 0.0f : -0.0f;
        }
        if (r.dir == Float3{0, 0, 0} || r.dir == Float3{-0.0f, 0, 0}) r.dir = Float3{0, 0, 1};
        r.tnear = pick(4) == 0 ? uniform(0, 1) : 0.0f;
        r.tfar = pick(4) == 0 ? uniform(0.5f, 2) : kInfinity;
        return r;
    }

private:
    std::mt19937 rng_;
};

bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }

void expect_lane_equals_reference(const LaneHits& out, int lane, bool ref_hit, const TriangleHit& ref,
                                  const char* what) {
    const bool hit = (out.mask >> lane) & 1u;
    ASSERT_EQ(hit, ref_hit) << what << " lane " << lane;
    if (hit) {
        ASSERT_TRUE(same_bits(out.t[lane], ref.t)) << what << " t " << out.t[lane] << " vs " << ref.t;
        ASSERT_TRUE(same_bits(out.u[lane], ref.u)) << what << " u " << out.u[lane] << " vs " << ref.u;
        ASSERT_TRUE(same_bits(out.v[lane], ref.v)) << what << " v " << out.v[lane] << " vs " << ref.v;
    }
}

// Lanes 0 .. n - 1 of out (lane i: tris[i]) each equal to the reference, no lane past n hit; returns
// the hits.
int expect_lanes_equal_reference(const LaneHits& out, const WatertightRay& w, const Triangle* tris, int n,
                                 const char* what) {
    int hits = 0;
    for (int i = 0; i < n; ++i) {
        TriangleHit ref{};
        const bool ref_hit = intersect_triangle(w, tris[i], ref);
        expect_lane_equals_reference(out, i, ref_hit, ref, what);
        hits += ref_hit;
    }
    EXPECT_EQ(out.mask >> n, 0u) << what << ": lanes past n must not hit";
    return hits;
}

std::vector<Isa> available_isas() {
    std::vector<Isa> isas;
    for (Isa isa : {Isa::scalar, Isa::sse42, Isa::avx2, Isa::avx512})
        if (isa_available(isa)) isas.push_back(isa);
    return isas;
}

}  // namespace

class TriangleKernelsTest : public ::testing::TestWithParam<Isa> {};

TEST_P(TriangleKernelsTest, OneRayManyTrianglesEqualsReference) {
    const TriangleKernels& k = triangle_kernels(GetParam());
    CaseGenerator gen(1234 + unsigned(GetParam()));
    std::uint64_t hits = 0, cases = 0;
    for (int iter = 0; iter < 250000; ++iter) {
        Triangle tris[8];
        const Triangle* ptrs[8];
        for (int i = 0; i < 8; ++i) {
            tris[i] = gen.triangle();
            ptrs[i] = &tris[i];
        }
        const Ray ray = gen.ray_towards(tris[gen.pick(8)]);
        const WatertightRay w = make_watertight_ray(ray);
        const int n = 1 + gen.pick(8);
        LaneHits out4, out8;
        k.ray_x4(w, ptrs, n < 4 ? n : 4, out4);
        k.ray_x8(w, ptrs, n, out8);
        expect_lanes_equal_reference(out4, w, tris, n < 4 ? n : 4, "ray_x4");
        hits += std::uint64_t(expect_lanes_equal_reference(out8, w, tris, n, "ray_x8"));
        cases += std::uint64_t(n);
        if (HasFailure()) return;
    }
    EXPECT_GT(cases, 1000000u);
    EXPECT_GT(hits, cases / 20) << "the generator should make many hits";
}

TEST_P(TriangleKernelsTest, OneRayCornerRowsEqualsReference) {
    // Up to 16 consecutive triangles of padded corner rows (as kdtree::PacketTables stores a leaf's),
    // starting anywhere in the rows, every lane equal to the reference bit for bit; lanes past n
    // never hit.
    const TriangleKernels& k = triangle_kernels(GetParam());
    CaseGenerator gen(4321 + unsigned(GetParam()));
    constexpr std::size_t kTriangles = 40, kStride = kTriangles + 16;
    std::vector<float> rows(9 * kStride, 0.0f);
    std::vector<Triangle> tris(kTriangles);
    std::uint64_t hits = 0, cases = 0;
    for (int iter = 0; iter < 60000; ++iter) {
        if (iter % 64 == 0) {
            for (std::size_t r = 0; r < kTriangles; ++r) {
                tris[r] = gen.triangle();
                const float* f = &tris[r].v0.x;
                for (int c = 0; c < 9; ++c) rows[std::size_t(c) * kStride + r] = f[c];
            }
        }
        const std::size_t first = std::size_t(gen.pick(int(kTriangles)));
        const int n = 1 + gen.pick(std::min(16, int(kTriangles - first)));
        const Ray ray = gen.ray_towards(tris[first + std::size_t(gen.pick(n))]);
        const WatertightRay w = make_watertight_ray(ray);
        LaneHits out;
        k.ray_rows(w, rows.data(), kStride, first, n, out);
        hits += std::uint64_t(expect_lanes_equal_reference(out, w, tris.data() + first, n, "ray_rows"));
        cases += std::uint64_t(n);
        if (HasFailure()) return;
    }
    EXPECT_GT(cases, 200000u);
    EXPECT_GT(hits, cases / 40) << "the generator should make many hits";
}

// Runs one packet against one triangle and compares every lane with the reference; returns the
// number of hits and adds the active lanes to cases.
static std::uint64_t check_packet(const TriangleKernels& k, const Packet16& p, const Triangle& tri,
                                  std::uint64_t& cases) {
    const WatertightPacket16 w = make_watertight_packet(p);
    LaneHits out;
    k.packet_x1(w, tri, out);
    std::uint64_t hits = 0;
    for (int i = 0; i < 16; ++i) {
        TriangleHit ref{};
        const bool active = (p.active >> i) & 1u;
        const bool ref_hit = active && intersect_triangle(make_watertight_ray(p.ray(i)), tri, ref);
        expect_lane_equals_reference(out, i, ref_hit, ref, "packet_x1");
        hits += ref_hit;
        cases += active;
    }
    return hits;
}

TEST_P(TriangleKernelsTest, PacketOneTriangleEqualsReference) {
    const TriangleKernels& k = triangle_kernels(GetParam());
    CaseGenerator gen(777 + unsigned(GetParam()));
    std::uint64_t hits = 0, cases = 0;
    for (int iter = 0; iter < 80000; ++iter) {
        const Triangle tri = gen.triangle();
        Packet16 p;
        p.active = gen.pick(10) == 0 ? std::uint32_t(gen.pick(1 << 16)) : 0xFFFFu;
        for (int i = 0; i < 16; ++i) p.set_ray(i, gen.ray_towards(tri));
        hits += check_packet(k, p, tri, cases);
    }
    EXPECT_GT(cases, 1000000u);
    EXPECT_GT(hits, cases / 20);
}

// Coherent packets (one origin, or one dominant axis), where the kernels permute the corners once
// for all lanes: still the reference's results bit for bit, including origins with -0 components.
TEST_P(TriangleKernelsTest, CoherentPacketEqualsReference) {
    const TriangleKernels& k = triangle_kernels(GetParam());
    CaseGenerator gen(4242 + unsigned(GetParam()));
    std::uint64_t hits = 0, cases = 0, shared_axes = 0, shared_origin = 0;
    for (int iter = 0; iter < 80000; ++iter) {
        const Triangle tri = gen.triangle();
        Packet16 p;
        p.active = gen.pick(10) == 0 ? std::uint32_t(gen.pick(1 << 16)) : 0xFFFFu;
        const Ray lead = gen.ray_towards(tri);
        const bool one_origin = gen.pick(2) == 0;
        for (int i = 0; i < 16; ++i) {
            Ray r = gen.ray_towards(tri);
            if (one_origin) {
                // Same origin bits in every lane (sometimes -0), aimed near the lead's target.
                r.org = lead.org;
                for (int c = 0; c < 3; ++c)
                    if (r.org[c] == 0.0f && gen.pick(2) == 0) r.org[c] = -0.0f;
                if (i > 0) r.org = p.ray(0).org;
                r.dir = lead.dir +
                        Float3{gen.uniform(-0.05f, 0.05f), gen.uniform(-0.05f, 0.05f), gen.uniform(-0.05f, 0.05f)};
            } else {
                // Nearby origins, nearly the same direction: the same dominant axis.
                r.org = lead.org + Float3{gen.uniform(-0.1f, 0.1f), gen.uniform(-0.1f, 0.1f), gen.uniform(-0.1f, 0.1f)};
                r.dir = lead.dir;
            }
            p.set_ray(i, r);
        }
        const WatertightPacket16 w = make_watertight_packet(p);
        shared_axes += w.same_axes;
        shared_origin += w.same_axes && w.same_origin;
        hits += check_packet(k, p, tri, cases);
    }
    EXPECT_GT(cases, 1000000u);
    EXPECT_GT(hits, cases / 20);
    EXPECT_GT(shared_axes, 40000u) << "most packets should share one axis order";
    EXPECT_GT(shared_origin, 20000u) << "many packets should share one origin";
}

INSTANTIATE_TEST_SUITE_P(EachIsa, TriangleKernelsTest, ::testing::ValuesIn(available_isas()),
                         [](const ::testing::TestParamInfo<Isa>& info) { return std::string(isa_name(info.param)); });

TEST(Isa, BestIsAvailableAndNamesRoundTrip) {
    EXPECT_TRUE(isa_available(best_isa()));
    for (Isa isa : available_isas()) EXPECT_EQ(parse_isa(isa_name(isa)), isa);
    EXPECT_THROW(parse_isa("neon"), std::exception);
}
