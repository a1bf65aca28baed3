// Dynamic scenes (section 8): random sequences of remove / transform / insert, after each of which
// every query answers exactly (bit for bit, both modes) as a field built afresh from the current
// geometry, which itself equals brute force; the tiles hold what a fresh build puts there.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>

#include "../kdtree/test_scenes.hpp"
#include "beamtrace/error.hpp"
#include "beamtrace/kdtree.hpp"
#include "beamtrace/vlf.hpp"

using namespace beamtrace;

namespace {

VlfOptions options(int l, int n, int d, const Box& bounds) {
    VlfOptions o;
    o.directions = l;
    o.tiles = n;
    o.depth = d;
    o.bounds = bounds;
    return o;
}

// The field's current scene: triangles taken out of it become zero-area points (never hit, never
// in a tile), so ids stay the same.
Scene current_scene(const VisibilityField& f) {
    std::vector<Float3> vertices;
    std::vector<std::uint32_t> indices;
    const std::span<const Triangle> tris = f.triangles();
    for (std::uint32_t id = 0; id < tris.size(); ++id) {
        const Triangle& t = tris[id];
        const bool in = f.contains(id);
        for (const Float3& p : {t.v0, t.v1, t.v2}) {
            indices.push_back(std::uint32_t(vertices.size()));
            vertices.push_back(in ? p : t.v0);
        }
    }
    return Scene(vertices, indices);
}

// A random rigid motion (rotation about a random axis through the box centre, then a shift) that
// keeps the moved triangles' corners inside `bounds` (checked by the caller).
Affine3 random_motion(std::mt19937& rng, const Box& scene_box) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    Float3 axis{u(rng), u(rng), u(rng)};
    axis = normalize(axis + Float3{0.0f, 0.0f, 1e-3f});
    const float angle = 0.5f * u(rng), c = std::cos(angle), s = std::sin(angle), k = 1.0f - c;
    Affine3 a;
    const float x = axis.x, y = axis.y, z = axis.z;
    const float m[3][3] = {{c + x * x * k, x * y * k - z * s, x * z * k + y * s},
                           {y * x * k + z * s, c + y * y * k, y * z * k - x * s},
                           {z * x * k - y * s, z * y * k + x * s, c + z * z * k}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) a.m[i][j] = m[i][j];
    const Float3 centre = scene_box.center(), shift = scene_box.extent() * (0.1f * u(rng));
    const Float3 rotated{a.m[0][0] * centre.x + a.m[0][1] * centre.y + a.m[0][2] * centre.z,
                         a.m[1][0] * centre.x + a.m[1][1] * centre.y + a.m[1][2] * centre.z,
                         a.m[2][0] * centre.x + a.m[2][1] * centre.y + a.m[2][2] * centre.z};
    a.t = centre - rotated + shift;
    return a;
}

bool inside(const Triangle& t, const Box& b) {
    for (const Float3& p : {t.v0, t.v1, t.v2})
        for (int k = 0; k < 3; ++k)
            if (p[k] < b.lower[k] || p[k] > b.upper[k]) return false;
    return true;
}

void expect_same(const VisibilityField& updated, const VisibilityField& fresh, const Scene& scene,
                 const std::vector<Ray>& rays, const std::string& what) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
        for (VlfMode mode : {VlfMode::exact, VlfMode::fast}) {
            const Hit a = updated.intersect(rays[i], mode), b = fresh.intersect(rays[i], mode);
            ASSERT_EQ(a.triangle, b.triangle) << what << " ray " << i;
            ASSERT_EQ(std::bit_cast<std::uint32_t>(a.t), std::bit_cast<std::uint32_t>(b.t)) << what << " ray " << i;
            ASSERT_EQ(a.u, b.u);
            ASSERT_EQ(a.v, b.v);
            ASSERT_EQ(updated.occluded(rays[i], mode), fresh.occluded(rays[i], mode)) << what << " ray " << i;
        }
        const Hit brute = intersect_brute_force(scene, rays[i]);
        ASSERT_EQ(updated.intersect(rays[i]).t, brute.t) << what << " ray " << i;
    }
}

}  // namespace

TEST(VlfDynamic, RandomUpdateSequencesEqualAFreshBuild) {
    const Scene start = test::random_soup(1500, 61, 0.15f);
    Box bounds = start.bounds();
    const Float3 grow = bounds.extent() * 0.5f;
    bounds = Box{bounds.lower - grow, bounds.upper + grow};
    for (auto [l, n, d] : {std::tuple{9, 16, 2}, std::tuple{33, 48, 4}, std::tuple{9, 7, 0}}) {
        SCOPED_TRACE(testing::Message() << "l " << l << " n " << n << " d " << d);
        VisibilityField field(start, options(l, n, d, bounds));
        field.build_all();
        std::mt19937 rng(std::uint32_t(l * 100 + n));
        std::vector<std::uint32_t> out;  // removed and not yet inserted
        for (int step = 0; step < 12; ++step) {
            // Remove a random set, move it (if the motion keeps it inside the bounds), put it back;
            // every third step leaves it out until the next step.
            std::vector<std::uint32_t> ids;
            for (std::uint32_t id = 0; id < field.triangles().size(); ++id)
                if (field.contains(id) && rng() % 10 == 0) ids.push_back(id);
            field.remove(ids);
            const Affine3 motion = random_motion(rng, start.bounds());
            std::vector<std::uint32_t> movable;
            for (std::uint32_t id : ids) {
                const Triangle& t = field.triangles()[id];
                if (inside(Triangle{motion.apply(t.v0), motion.apply(t.v1), motion.apply(t.v2)}, bounds))
                    movable.push_back(id);
            }
            field.transform(movable, motion);
            if (step % 5 == 4 && !movable.empty()) {  // squash one onto a line: zero area
                Affine3 flat;
                flat.m[1][1] = flat.m[2][2] = 0.0f;
                flat.t = Float3{0, bounds.center().y, bounds.center().z};
                const std::uint32_t one[1] = {movable.front()};
                field.transform(one, flat);
            }
            field.insert(out);
            out.clear();
            if (step % 3 == 2)
                out = ids;
            else
                field.insert(ids);

            const Scene scene = current_scene(field);
            VisibilityField fresh(scene, options(l, n, d, bounds));
            fresh.build_all();
            EXPECT_EQ(field.stats().tile_entries, fresh.stats().tile_entries) << "step " << step;
            EXPECT_EQ(field.stats().leaves, fresh.stats().leaves) << "step " << step;
            std::vector<Ray> rays = test::random_rays(scene.bounds(), 1500, 70 + std::uint32_t(step));
            const std::vector<Ray> axis = test::axis_rays(scene, 300, 80 + std::uint32_t(step));
            rays.insert(rays.end(), axis.begin(), axis.end());
            expect_same(field, fresh, scene, rays, "step " + std::to_string(step));
            if (HasFatalFailure()) return;
        }
    }
}

TEST(VlfDynamic, LazyPsfsBuiltAfterUpdatesSeeTheNewGeometry) {
    const Scene start = test::random_soup(800, 62, 0.2f);
    VisibilityField field(start, options(33, 32, 4, start.bounds()));
    Ray r;
    r.org = start.bounds().center() - Float3{0, 0, 3};
    r.dir = {0, 0, 1};
    field.intersect(r);  // one PSF built before the update, the others after
    ASSERT_EQ(field.stats().psfs_built, 1u);
    std::vector<std::uint32_t> ids;
    for (std::uint32_t id = 0; id < 800; id += 3) ids.push_back(id);
    field.remove(ids);
    Affine3 mirror;
    mirror.m[0][0] = -1.0f;
    mirror.t = Float3{start.bounds().lower.x + start.bounds().upper.x, 0, 0};
    field.transform(ids, mirror);
    field.insert(ids);
    const Scene scene = current_scene(field);
    const VisibilityField fresh(scene, options(33, 32, 4, start.bounds()));
    expect_same(field, fresh, scene, test::random_rays(scene.bounds(), 4000, 63), "mirrored");
    EXPECT_EQ(field.stats().psfs_built, 33u);
}

TEST(VlfDynamic, UpdatesCheckTheirInput) {
    const Scene s = test::random_soup(50, 64);
    const Float3 grow = s.bounds().extent() * 0.1f;
    VisibilityField field(s, options(9, 8, 2, Box{s.bounds().lower - grow, s.bounds().upper + grow}));
    const std::uint32_t a[1] = {3}, twice[2] = {4, 4}, far[1] = {50};
    EXPECT_THROW(field.remove(far), Error);
    EXPECT_THROW(field.remove(twice), Error);
    EXPECT_THROW(field.insert(a), Error);                // still in
    EXPECT_THROW(field.transform(a, Affine3{}), Error);  // must be removed first
    field.remove(a);
    EXPECT_FALSE(field.contains(3));
    EXPECT_THROW(field.remove(a), Error);
    Affine3 away;
    away.t = s.bounds().extent() * 10.0f;
    field.transform(a, away);
    EXPECT_THROW(field.insert(a), Error);  // outside the bounds
    EXPECT_FALSE(field.contains(3));
    Affine3 back;
    back.t = away.t * -1.0f;
    field.transform(a, back);
    field.insert(a);
    EXPECT_TRUE(field.contains(3));
}
