// Extremes.AxisDirections*: direction components exactly 0 and -0 (rays along and exactly inside
// the kd-tree's split planes, through vertices along the axes, on VLF's tile borders), nearly
// parallel rays (components of 1e-7, of FLT_MIN and denormal ones), and rays grazing along
// triangle edges and inside triangle planes. Zero `mismatch` for every exact engine, against
// Embree and against exact geometry.
#include <gtest/gtest.h>

#include <cfloat>
#include <random>
#include <set>

#include "extremes/engine_checks.hpp"
#include "common/access.hpp"
#include "kdtree/kd_node.hpp"
#include "kdtree/test_scenes.hpp"
#include "vlf/directions/canonical_frame.hpp"

namespace beamtrace::test {
namespace {

using workload::Mode;

scenes::SceneSource source_of(const std::string& name, Scene scene) {
    const scenes::Camera camera = scenes::frame_from_outside(scene.bounds());
    return scenes::SceneSource{name, std::move(scene), camera, name};
}

std::vector<scenes::SceneSource> axis_scenes() {
    std::vector<scenes::SceneSource> s;
    s.push_back(source_of("stacked boxes", stacked_boxes(40, 3)));
    s.push_back(scenes::load_scene("tetra:3"));
    s.push_back(scenes::load_scene("sphereflake:0"));
    return s;
}

float signed_zero(std::mt19937& rng) { return (rng() % 2) ? 0.0f : -0.0f; }

// A point in the box grown by 20% on every side.
Float3 around(const Box& b, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(-0.2f, 1.2f);
    const Float3 e = b.extent();
    return b.lower + Float3{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z};
}

Float3 random_direction(std::mt19937& rng) {
    std::uniform_real_distribution<float> d(-1.0f, 1.0f);
    Float3 v;
    do v = Float3{d(rng), d(rng), d(rng)};
    while (dot(v, v) < 1e-2f);
    return v;
}

// The split planes of a kd-tree built for the scene (at most `limit`, spread over the tree).
std::vector<std::pair<int, float>> split_planes(const Scene& scene, std::size_t limit) {
    const KdTree tree = KdTree::build(scene);
    std::set<std::pair<int, float>> planes;
    for (const KdNode& n : detail::Access::impl(tree).nodes)
        if (!n.is_leaf()) planes.insert({n.axis(), n.split});
    std::vector<std::pair<int, float>> all(planes.begin(), planes.end()), picked;
    const std::size_t step = std::max<std::size_t>(1, all.size() / limit);
    for (std::size_t i = 0; i < all.size(); i += step) picked.push_back(all[i]);
    return picked;
}

// Rays lying exactly in split planes: the plane's component of the direction is +0 or -0; some are
// axis-parallel inside the plane (a second zero component).
std::vector<Ray> in_split_planes(const Scene& scene, unsigned seed) {
    std::mt19937 rng(seed);
    std::vector<Ray> rays;
    for (const auto& [axis, split] : split_planes(scene, 150)) {
        for (int i = 0; i < 6; ++i) {
            Ray r;
            r.org = around(scene.bounds(), rng);
            r.org[axis] = split;
            r.dir = random_direction(rng);
            r.dir[axis] = signed_zero(rng);
            if (i >= 4) r.dir[(axis + 1 + i % 2) % 3] = signed_zero(rng);
            rays.push_back(r);
        }
    }
    return rays;
}

// The same rays tilted out of their planes by a component of `tilt` times the largest one.
std::vector<Ray> tilted(std::vector<Ray> rays, float tilt, unsigned seed) {
    std::mt19937 rng(seed);
    for (Ray& r : rays) {
        const float m = std::max({std::fabs(r.dir.x), std::fabs(r.dir.y), std::fabs(r.dir.z)});
        for (int k = 0; k < 3; ++k)
            if (r.dir[k] == 0.0f) r.dir[k] = ((rng() % 2) ? tilt : -tilt) * m;
    }
    return rays;
}

// Axis-parallel rays through vertices: the origin is a vertex moved outside the box along one axis.
std::vector<Ray> through_vertices_along_axes(const Scene& scene, int n, unsigned seed) {
    std::mt19937 rng(seed);
    const auto verts = scene.vertices();
    const Box& b = scene.bounds();
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        const int axis = int(rng() % 3);
        const bool up = rng() % 2;
        Ray r;
        r.org = verts[rng() % verts.size()];
        r.org[axis] = up ? b.lower[axis] - 0.5f * b.extent()[axis] : b.upper[axis] + 0.5f * b.extent()[axis];
        r.dir = Float3{signed_zero(rng), signed_zero(rng), signed_zero(rng)};
        r.dir[axis] = up ? 1.0f : -1.0f;
        rays.push_back(r);
    }
    return rays;
}

// Rays along triangle edges (the line of the edge), inside triangle planes through their centroid,
// and along edges lifted off the surface by 1e-6 of the edge's length.
std::vector<Ray> grazing(const Scene& scene, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        const std::uint32_t id = std::uint32_t(rng() % scene.triangle_count());
        if (scene.is_degenerate(id)) continue;
        const Triangle& t = scene.triangle(id);
        const Float3 c[3] = {t.v0, t.v1, t.v2};
        const int k = int(rng() % 3);
        const Float3 a = c[k], b = c[(k + 1) % 3], e = b - a;
        const Float3 normal = normalize(cross(t.v1 - t.v0, t.v2 - t.v0));
        const Float3 centroid = (t.v0 + t.v1 + t.v2) * (1.0f / 3.0f);
        rays.push_back(Ray{a - e * 0.5f, 0.0f, e, kInfinity});
        rays.push_back(Ray{b + e * 0.5f, 0.0f, e * -1.0f, kInfinity});
        rays.push_back(Ray{centroid - e, 0.0f, e, kInfinity});
        rays.push_back(Ray{a - e * 0.5f + normal * (1e-6f * length(e)), 0.0f, e, kInfinity});
    }
    return rays;
}

// Rays exactly along VLF beam directions (the field's default set) with origins on tile borders of
// that direction's subfield (as near as float gets), for a field with `tiles` tiles per side.
std::vector<Ray> on_tile_borders(const Scene& scene, int directions, int tiles, int n, unsigned seed) {
    std::mt19937 rng(seed);
    const DirectionSet set(directions);
    const vlf::TileGrid grid = vlf::TileGrid::around(scene.bounds(), tiles);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        const Float3 w = set.direction(int(rng() % std::uint32_t(set.size())));
        const vlf::CanonicalFrame f = vlf::CanonicalFrame::towards(w);
        // Canonical (x, y) on a tile corner, edge or border line; z before the scene.
        double x = grid.edge(int(rng() % std::uint32_t(tiles + 1)));
        double y = (rng() % 2) ? grid.edge(int(rng() % std::uint32_t(tiles + 1))) : u(rng) * grid.radius;
        if (rng() % 2) std::swap(x, y);
        const double z = -1.5 * grid.radius;
        Ray r;
        for (int k = 0; k < 3; ++k) {
            const double e1[3] = {f.e1.x, f.e1.y, f.e1.z}, e2[3] = {f.e2.x, f.e2.y, f.e2.z},
                         e3[3] = {f.e3.x, f.e3.y, f.e3.z}, c[3] = {grid.centre.x, grid.centre.y, grid.centre.z};
            r.org[k] = float(c[k] + x * e1[k] + y * e2[k] + z * e3[k]);
        }
        r.dir = (rng() % 2) ? w : w * -1.0f;
        if (r.dir == w * -1.0f) r.org = r.org + w * float(3.0 * grid.radius);  // start beyond the far side
        rays.push_back(r);
    }
    return rays;
}

// An orthographic image looking down -z: pixel origins on a grid that includes the box's own
// bounds, directions (dx, dy, -1) per pixel from `slope` (0 gives +0/-0 mixed in every packet).
std::vector<Ray> orthographic(const Box& b, int side, float slope) {
    std::vector<Ray> rays;
    for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i) {
            Ray r;
            r.org = Float3{b.lower.x + b.extent().x * float(i) / float(side - 1),
                           b.lower.y + b.extent().y * float(j) / float(side - 1), b.upper.z + b.extent().z};
            const float sx = slope * float(i - side / 2), sy = slope * float(j - side / 2);
            r.dir = Float3{sx == 0.0f && (i + j) % 2 ? -0.0f : sx, sy == 0.0f && i % 2 ? -0.0f : sy, -1.0f};
            rays.push_back(r);
        }
    return rays;
}

// Occlusion rays: the same rays as segments ending halfway through the box.
std::vector<Ray> as_segments(std::vector<Ray> rays, const Box& b) {
    for (Ray& r : rays) r.tfar = 0.75f * b.diagonal() / length(r.dir);
    return rays;
}

EngineChoice fields() {
    EngineChoice choice;
    choice.options.vlf.directions = 129;
    choice.options.vlf.tiles = 32;
    return choice;
}

void check(const scenes::SceneSource& source, const std::vector<EngineUnderTest>& engines, const std::string& what,
           const std::vector<Ray>& rays, int image_width = 0) {
    for (Mode mode : {Mode::primary, Mode::shadow}) {
        const std::vector<Ray> r = mode == Mode::primary ? rays : as_segments(rays, source.scene.bounds());
        workload::RaySet set = image_width > 0 ? image_ray_set(r, image_width, mode) : ray_set(r, mode);
        expect_exact_engines_clean(check_engines(engines, workload_for(source, std::move(set)),
                                                 source.name + " " + what + " " + workload::to_string(mode), true));
    }
}

}  // namespace

TEST(Extremes, AxisDirectionsInsideSplitPlanes) {
    for (const scenes::SceneSource& s : axis_scenes()) {
        const auto engines = build_engines(s.scene, fields());
        check(s, engines, "in split planes", in_split_planes(s.scene, 1));
        check(s, engines, "through vertices along axes", through_vertices_along_axes(s.scene, 1500, 2));
        check(s, engines, "axis_rays", axis_rays(s.scene, 1500, 3));
    }
}

TEST(Extremes, AxisDirectionsNearlyParallel) {
    for (const scenes::SceneSource& s : axis_scenes()) {
        const auto engines = build_engines(s.scene, fields());
        const std::vector<Ray> planar = in_split_planes(s.scene, 4);
        check(s, engines, "tilted 1e-7", tilted(planar, 1e-7f, 5));
        check(s, engines, "tilted FLT_MIN", tilted(planar, FLT_MIN, 6));
        check(s, engines, "tilted denormal", tilted(planar, 1e-40f, 7));
    }
}

TEST(Extremes, AxisDirectionsOrthographicImages) {
    for (const scenes::SceneSource& s : axis_scenes()) {
        const auto engines = build_engines(s.scene, fields());
        for (float slope : {0.0f, 1e-7f, 1e-4f})
            check(s, engines, "orthographic slope " + std::to_string(slope), orthographic(s.scene.bounds(), 48, slope),
                  48);
    }
}

TEST(Extremes, AxisDirectionsOnVlfTileBorders) {
    for (const scenes::SceneSource& s : axis_scenes()) {
        const auto engines = build_engines(s.scene, fields());
        check(s, engines, "on tile borders", on_tile_borders(s.scene, 129, 32, 3000, 8));
    }
}

TEST(Extremes, AxisDirectionsGrazingEdgesAndFaces) {
    for (const scenes::SceneSource& s : axis_scenes()) {
        const auto engines = build_engines(s.scene, fields());
        check(s, engines, "grazing", grazing(s.scene, 800, 9));
    }
}

}  // namespace beamtrace::test
