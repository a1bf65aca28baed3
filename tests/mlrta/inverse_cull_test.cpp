// Inverse frustum culling at inner nodes (section 3.3, Figure 3 c-d): a cell split by x = 1 and beams
// whose rectangle on the split plane lies beyond the cell's face on another axis. Rays moving further
// out miss the child beyond the plane (the far one); rays moving in miss the child before it (the
// near one). Then conservativeness: any child some ray of the beam really enters keeps its bit.
#include <gtest/gtest.h>

#include "hand_tree.hpp"
#include <bit>
#include <cmath>

#include "mlrta/inverse_frustum_cull.hpp"
#include "mlrta/split_rectangle.hpp"

using namespace beamtrace;
using namespace beamtrace::mlrta;
using namespace beamtrace::mlrta::test;

namespace {

// The cell [0,2] x [0,1] x [0,1] with the split plane x = 1 (the plane abcd of Figure 3).
const Box kCell{{0, 0, 0}, {2, 1, 1}};
const Box kLowerChild{{0, 0, 0}, {1, 1, 1}};
const Box kUpperChild{{1, 0, 0}, {2, 1, 1}};
constexpr float kSplit = 1.0f;

// Rays through points of the plane x = 1 around (1, y, z), with direction signs sx, sy, sz, starting
// half a unit before the plane along x (inside the near child's slab, moving towards the plane). The
// directions and crossing points vary little, so the beam's rectangle on the plane stays small.
std::vector<Ray> through_plane(Rng& rng, float y, float z, int sx, int sy, int sz, float spread = 0.02f) {
    std::vector<Ray> rays;
    for (int i = 0; i < 16; ++i) {
        const Float3 d{float(sx), float(sy) * uniform(rng, 0.4f, 0.45f), float(sz) * uniform(rng, 0.05f, 0.06f)};
        const Float3 q{kSplit, y + uniform(rng, -spread, spread), z + uniform(rng, -spread, spread)};
        rays.push_back(Ray{q - d * 0.5f, 0.0f, d, kInfinity});
    }
    return rays;
}

std::uint8_t truth(const std::vector<Ray>& rays) {
    std::uint8_t m = kNoChild;
    for (const Ray& r : rays) {
        if (segment_meets_box(r, kLowerChild)) m |= kLower;
        if (segment_meets_box(r, kUpperChild)) m |= kUpper;
    }
    return m;
}

}  // namespace

// Figure 3 c-d along y: the rectangle below the cell (y < 0 on x = 1) or above it (y > 1), rays moving
// down or up, for both signs of the x direction (which decides which child is near).
TEST(MlrtaInverseCull, Figure3RectangleBeyondTheCellInY) {
    Rng rng(11);
    for (int sx : {1, -1})
        for (bool below : {true, false})
            for (int sy : {1, -1}) {
                const std::vector<Ray> rays = through_plane(rng, below ? -0.1f : 1.1f, 0.5f, sx, sy, 1);
                const ChildMask near = sx > 0 ? kLower : kUpper, far = sx > 0 ? kUpper : kLower;
                // Below the cell and moving down (Figure 3c), or above and moving up: past the plane
                // the rays are further out, only the near child. Moving in (Figure 3d): only the far one.
                const bool moving_out = below ? sy < 0 : sy > 0;
                const ChildMask expected = moving_out ? near : far;
                for (const Beam& beam : {beam_of(rays, &kCell), packet_beam_of(rays, &kCell)}) {
                    ASSERT_TRUE(beam.coherent);
                    EXPECT_EQ(int(cull_split(beam, kCell, 0, kSplit)), int(expected))
                        << "sx " << sx << (below ? " below" : " above") << " sy " << sy;
                }
                EXPECT_EQ(int(truth(rays)), int(expected)) << "the hand-made rays really enter that child only";
            }
}

TEST(MlrtaInverseCull, Figure3RectangleBeyondTheCellInZ) {
    Rng rng(12);
    for (int sx : {1, -1})
        for (bool below : {true, false})
            for (int sz : {1, -1}) {
                // Steeper in z than in y here: swap the roles of y and z in the hand-made rays.
                std::vector<Ray> rays = through_plane(rng, below ? -0.1f : 1.1f, 0.5f, sx, sz, 1);
                for (Ray& r : rays) {
                    std::swap(r.org.y, r.org.z);
                    std::swap(r.dir.y, r.dir.z);
                }
                const ChildMask near = sx > 0 ? kLower : kUpper, far = sx > 0 ? kUpper : kLower;
                const bool moving_out = below ? sz < 0 : sz > 0;
                const ChildMask expected = moving_out ? near : far;
                for (const Beam& beam : {beam_of(rays, &kCell), packet_beam_of(rays, &kCell)}) {
                    ASSERT_TRUE(beam.coherent);
                    EXPECT_EQ(int(cull_split(beam, kCell, 0, kSplit)), int(expected))
                        << "sx " << sx << (below ? " below" : " above") << " sz " << sz;
                }
                EXPECT_EQ(int(truth(rays)), int(expected));
            }
}

TEST(MlrtaInverseCull, StartsOnOneSideMovingAwayKeepThatSideOnly) {
    Rng rng(13);
    for (int sx : {1, -1}) {
        // Starts beyond the plane in the direction of travel; the rectangle on x = 1 (behind the starts)
        // straddles the whole cell face, so only the start test can decide.
        std::vector<Ray> rays;
        for (int i = 0; i < 16; ++i) {
            const Float3 o{sx > 0 ? uniform(rng, 1.2f, 1.8f) : uniform(rng, 0.2f, 0.8f), uniform(rng, 0.3f, 0.7f),
                           uniform(rng, 0.3f, 0.7f)};
            rays.push_back(
                Ray{o, 0.0f, {float(sx), uniform(rng, 0.01f, 0.02f), uniform(rng, 0.01f, 0.02f)}, kInfinity});
        }
        const Beam beam = beam_of(rays, &kCell);
        const ChildMask expected = sx > 0 ? kUpper : kLower;
        EXPECT_EQ(int(cull_split(beam, kCell, 0, kSplit)), int(expected)) << "sx " << sx;
        EXPECT_EQ(int(truth(rays)), int(expected));
        // The same starts moving towards the plane keep both children.
        for (Ray& r : rays) r.dir.x = -r.dir.x;
        EXPECT_EQ(int(cull_split(beam_of(rays, &kCell), kCell, 0, kSplit)), int(kBothChildren)) << "sx " << -sx;
    }
}

TEST(MlrtaInverseCull, BeamCrossingThePlaneInsideTheFaceKeepsBothChildren) {
    Rng rng(14);
    for (int sx : {1, -1})
        for (int sy : {1, -1})
            for (int sz : {1, -1}) {
                const std::vector<Ray> rays = through_plane(rng, 0.5f, 0.5f, sx, sy, sz, 0.3f);
                EXPECT_EQ(int(truth(rays)), int(kBothChildren));
                EXPECT_EQ(int(cull_split(beam_of(rays, &kCell), kCell, 0, kSplit)), int(kBothChildren))
                    << sx << " " << sy << " " << sz;
            }
}

// Random cells, split planes and coherent beams (narrow and wide, one origin or many, segments and
// half-lines): every child some ray's segment really meets (closed boxes, double precision) must be
// kept. Single-child answers must occur often, or the test would show nothing.
TEST(MlrtaInverseCull, ConservativeForRandomBeamsAndCells) {
    Rng rng(15);
    int single = 0, trials = 0;
    for (int trial = 0; trial < 40000; ++trial) {
        Box cell;
        cell.extend(Float3{uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2)});
        cell.extend(Float3{uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2)});
        const int k = int(rng() % 3);
        const float split = rng() % 8 == 0 ? cell.lower[k] : uniform(rng, cell.lower[k], cell.upper[k]);
        const Box scene{{-4, -4, -4}, {4, 4, 4}};
        Float3 dir;
        for (int a = 0; a < 3; ++a) dir[a] = (rng() % 2 ? 1.0f : -1.0f) * uniform(rng, 0.02f, 1.0f);
        const float spread_org = rng() % 3 == 0 ? 0.0f : uniform(rng, 0.0f, 0.5f);
        std::vector<Ray> rays =
            bundle(rng, 1 + int(rng() % 16), {uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3)},
                   spread_org, dir, uniform(rng, 0.0f, 0.5f));
        for (Ray& r : rays) {
            if (rng() % 4 == 0) r.tnear = uniform(rng, 0.0f, 2.0f);
            if (rng() % 4 == 0) r.tfar = r.tnear + uniform(rng, 0.0f, 4.0f);
        }
        Box lower = cell, upper = cell;
        lower.upper[k] = split;
        upper.lower[k] = split;
        if (rng() % 3 == 0) {  // one ray grazing a corner or an edge of a child: the padding at work
            const Box& child = rng() % 2 ? lower : upper;
            Float3 target;
            for (int a = 0; a < 3; ++a)
                target[a] = rng() % 3 ? (rng() % 2 ? child.lower[a] : child.upper[a])
                                      : uniform(rng, child.lower[a], child.upper[a]);
            rays[0].org = target - rays[0].dir * uniform(rng, -1.0f, 3.0f);
            rays[0].tnear = 0.0f;
            rays[0].tfar = kInfinity;
        }
        const Beam beam = trial % 2 ? beam_of(rays, &scene) : packet_beam_of(rays, &scene);
        ASSERT_TRUE(beam.coherent);
        bool lo = false, hi = false;
        for (const Ray& r : rays) {
            lo = lo || segment_meets_box(r, lower);
            hi = hi || segment_meets_box(r, upper);
        }
        if (!lo && !hi) continue;  // the beam misses the cell: the parent would have been culled
        ++trials;
        const ChildMask mask = cull_split(beam, cell, k, split);
        ASSERT_TRUE(!lo || (mask & kLower)) << "trial " << trial << ": a ray enters the lower child";
        ASSERT_TRUE(!hi || (mask & kUpper)) << "trial " << trial << ": a ray enters the upper child";
        if (mask == kLower || mask == kUpper) ++single;
    }
    EXPECT_GT(trials, 2000);
    EXPECT_GT(single, trials / 10);
}

// Rays nearly parallel to a plane: one direction component tiny (down to denormals), where reciprocal
// slopes overflow to infinity and 0 * infinity must not turn a bound into NaN that culls a child.
TEST(MlrtaInverseCull, ConservativeForRaysNearlyParallelToAPlane) {
    Rng rng(16);
    int trials = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        Box cell;
        cell.extend(Float3{uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2)});
        cell.extend(Float3{uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2)});
        const int k = int(rng() % 3);
        const float split = uniform(rng, cell.lower[k], cell.upper[k]);
        const Box scene{{-4, -4, -4}, {4, 4, 4}};
        Float3 dir;
        for (int a = 0; a < 3; ++a) dir[a] = (rng() % 2 ? 1.0f : -1.0f) * uniform(rng, 0.1f, 1.0f);
        const int flat = int(rng() % 3);
        const float tiny[] = {1e-8f, 1e-20f, 1e-38f, 1e-41f, 1e-45f};
        dir[flat] = (dir[flat] > 0 ? 1.0f : -1.0f) * tiny[rng() % 5];
        // Some starts exactly on the split plane, where the offset to the plane is 0.
        Float3 org{uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3)};
        if (rng() % 2) org[k] = split;
        std::vector<Ray> rays = bundle(rng, 1 + int(rng() % 8), org, rng() % 2 ? 0.0f : 0.3f, dir, 0.2f);
        const Beam beam = trial % 2 ? beam_of(rays, &scene) : packet_beam_of(rays, &scene);
        ASSERT_TRUE(beam.coherent);
        Box lower = cell, upper = cell;
        lower.upper[k] = split;
        upper.lower[k] = split;
        bool lo = false, hi = false;
        for (const Ray& r : rays) {
            lo = lo || segment_meets_box(r, lower);
            hi = hi || segment_meets_box(r, upper);
        }
        if (!lo && !hi) continue;
        ++trials;
        const ChildMask mask = cull_split(beam, cell, k, split);
        ASSERT_TRUE(!lo || (mask & kLower))
            << "trial " << trial << ": a ray enters the lower child, axis " << k << ", tiny component on axis " << flat;
        ASSERT_TRUE(!hi || (mask & kUpper))
            << "trial " << trial << ": a ray enters the upper child, axis " << k << ", tiny component on axis " << flat;
    }
    EXPECT_GT(trials, 1000);
}

// The 4-wide SSE rectangle on a split plane (split_rectangle.hpp) is plane_range's for both other
// axes, bit for bit, for random beams (one origin or many, either sign, finite or infinite
// segments, with or without scene padding) and planes on every axis.
TEST(MlrtaInverseCull, SseRectangleEqualsTheScalarRangesBitForBit) {
    Rng rng(31);
    int compared = 0;
    for (int iter = 0; iter < 20000; ++iter) {
        const Float3 org{uniform(rng, -50, 50), uniform(rng, -50, 50), uniform(rng, -50, 50)};
        Float3 dir{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
        for (int k = 0; k < 3; ++k)
            if (std::fabs(dir[k]) < 0.01f) dir[k] = 0.01f;
        std::vector<Ray> rays =
            bundle(rng, 2 + int(rng() % 20), org, rng() % 2 ? 0.0f : uniform(rng, 0, 5), dir, uniform(rng, 0, 0.3f));
        if (rng() % 2)
            for (Ray& r : rays) r.tfar = uniform(rng, 1, 100);
        Box scene{{-100, -100, -100}, {100, 100, 100}};
        const Beam beam = beam_of(rays, rng() % 4 ? &scene : nullptr);
        if (!beam.coherent) continue;
        for (int k = 0; k < 3; ++k) {
            const float p = uniform(rng, -120, 120);
            float expected[4], got[4];
            split_rectangle_reference(beam, k, p, expected);
            _mm_storeu_ps(got, split_rectangle(beam, k, p));
            for (int i = 0; i < 4; ++i)
                ASSERT_EQ(std::bit_cast<std::uint32_t>(got[i]), std::bit_cast<std::uint32_t>(expected[i]))
                    << "iteration " << iter << " axis " << k << " lane " << i << ": " << got[i] << " vs "
                    << expected[i];
            ++compared;
        }
    }
    EXPECT_GT(compared, 50000);
}
