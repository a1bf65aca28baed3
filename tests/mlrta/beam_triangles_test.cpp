// A beam with one origin against single triangles (beam_triangles.hpp): the frustum is the beam's,
// and a triangle said to block the beam is hit by every ray of it (single-precision watertight
// test) within its segment, no farther than the reported distance, and inside the cell when that
// is claimed. Also the other way round: the test finds blockers (triangles far larger than the
// beam's cross-section straight ahead).
#include <gtest/gtest.h>

#include <cmath>

#include "common/triangle_reference.hpp"
#include "hand_tree.hpp"
#include "mlrta/beam_triangles.hpp"

using namespace beamtrace;
using namespace beamtrace::mlrta;
using namespace beamtrace::mlrta::test;

namespace {

Float3 random_direction(Rng& rng) {
    for (;;) {
        const Float3 d{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
        if (std::fabs(d.x) > 0.05f && std::fabs(d.y) > 0.05f && std::fabs(d.z) > 0.05f) return d;
    }
}

// A triangle across the line org + t dir at distance `at`, of size `size`, at a random tilt; its
// corners moved off the line's axis by `offset` (so that some beams pass its edges).
Triangle across(Rng& rng, Float3 org, Float3 dir, float at, float size, float offset) {
    const Float3 c = org + dir * at;
    const Float3 shift{uniform(rng, -offset, offset), uniform(rng, -offset, offset), uniform(rng, -offset, offset)};
    Float3 p[3];
    for (Float3& q : p)
        q = c + shift + Float3{uniform(rng, -size, size), uniform(rng, -size, size), uniform(rng, -size, size)};
    return Triangle{p[0], p[1], p[2]};
}

// A large equilateral triangle perpendicular to the line at distance `at`, centred on it.
Triangle facing(Float3 org, Float3 dir, float at, float size) {
    const Float3 d = normalize(dir);
    const Float3 u = normalize(cross(d, std::fabs(d.x) < 0.5f ? Float3{1, 0, 0} : Float3{0, 1, 0}));
    const Float3 v = cross(d, u);
    const Float3 c = org + dir * at;
    return Triangle{c + u * size, c + (u * -0.5f + v * 0.866f) * size, c + (u * -0.5f - v * 0.866f) * size};
}

}  // namespace

TEST(MlrtaBeamTriangles, BlockersAreHitByEveryRayInsideTheirCell) {
    Rng rng(81);
    int blocks = 0, inside = 0, cases = 0;
    for (int iter = 0; iter < 20000; ++iter) {
        const Float3 org{uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5)};
        const Float3 dir = random_direction(rng) * uniform(rng, 0.5f, 3.0f);
        std::vector<Ray> rays = bundle(rng, 2 + int(rng() % 15), org, 0.0f, dir, uniform(rng, 0.0f, 0.05f));
        const bool finite = rng() % 3 == 0;
        for (Ray& r : rays) {
            r.tnear = rng() % 2 ? 0.0f : uniform(rng, 0.0f, 0.3f);
            r.tfar = finite ? uniform(rng, 1.0f, 4.0f) : kInfinity;
        }
        const Beam beam = beam_of(rays);
        ASSERT_TRUE(beam.one_origin);
        const OneOriginFrustum f = beam_frustum(beam);
        ASSERT_TRUE(f.valid);
        const float at = uniform(rng, 0.2f, 3.0f);
        const Triangle tri = across(rng, org, dir, at, uniform(rng, 0.01f, 20.0f), uniform(rng, 0.0f, 0.5f));
        // A cell around the hits, sometimes too small to hold them all.
        Box cell;
        const Float3 c = org + dir * at;
        const float half = uniform(rng, 0.01f, 5.0f);
        cell.extend(c - Float3{half, half, half});
        cell.extend(c + Float3{half, half, half});
        const BeamBlock b = beam_block(beam, f, tri, cell);
        ++cases;
        if (!b.blocks) continue;
        ++blocks;
        inside += b.inside;
        for (const Ray& r : rays) {
            TriangleHit h;
            ASSERT_TRUE(intersect_triangle(make_watertight_ray(r), tri, h)) << "iteration " << iter;
            ASSERT_GE(h.t, r.tnear) << "iteration " << iter;
            ASSERT_LE(h.t, r.tfar) << "iteration " << iter;
            const int m = beam.main_axis;
            ASSERT_LE(double(h.t) * std::fabs(double(r.dir[m])), b.far * (1.0 + 1e-5)) << "iteration " << iter;
            if (b.inside) {
                const Float3 p = r.org + r.dir * h.t;
                for (int k = 0; k < 3; ++k) {
                    const float slack = 1e-5f * (std::fabs(p[k]) + length(r.dir) * h.t + 1.0f);
                    ASSERT_GE(p[k], cell.lower[k] - slack) << "iteration " << iter;
                    ASSERT_LE(p[k], cell.upper[k] + slack) << "iteration " << iter;
                }
            }
        }
    }
    EXPECT_GT(blocks, cases / 10) << "large triangles straight ahead should often block";
    EXPECT_GT(inside, blocks / 10);
    EXPECT_LT(blocks, cases - cases / 10) << "small or shifted triangles should often not";
}

TEST(MlrtaBeamTriangles, NoBlockerForBeamsWithSeveralOriginsOrTrianglesBehind) {
    Rng rng(82);
    for (int iter = 0; iter < 2000; ++iter) {
        const Float3 org{uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5)};
        const Float3 dir = random_direction(rng);
        const Triangle ahead = facing(org, dir, 1.0f, 50.0f), behind = facing(org, dir, -1.0f, 50.0f);
        Box everything;
        everything.extend(Float3{-1e3f, -1e3f, -1e3f});
        everything.extend(Float3{1e3f, 1e3f, 1e3f});
        const Beam several = beam_of(bundle(rng, 8, org, 0.01f, dir, 0.01f));
        ASSERT_FALSE(several.one_origin);
        EXPECT_FALSE(beam_block(several, beam_frustum(several), ahead, everything).blocks);
        const Beam one = beam_of(bundle(rng, 8, org, 0.0f, dir, 0.01f));
        EXPECT_FALSE(beam_block(one, beam_frustum(one), behind, everything).blocks) << "iteration " << iter;
        EXPECT_TRUE(beam_block(one, beam_frustum(one), ahead, everything).blocks) << "iteration " << iter;
    }
}
