// Watertight.*: rays from outside aimed exactly at the shared vertices and edge midpoints of closed
// meshes (bunny, tetra, sphereflake), from many directions, each entering the surface there: the
// direction makes an angle of more than 3 degrees with every face around the target, pointing in.
// Such a ray must hit the surface no later than the target (t <= 1 + 1e-4, t = 1 at the target):
// a ray that hits nothing or hits later has passed through the surface. Leaks are counted per
// engine; zero allowed for every exact engine. Embree's count is printed for docs/robustness.md;
// vlf-fast, approximate by design, is left out.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>

#include "extremes/engine_checks.hpp"
#include "extremes/exact_reference.hpp"
#include "support/differential.hpp"

namespace beamtrace::test {
namespace {

using workload::Mode;

constexpr float kLate = 1e-4f;  // t beyond 1 + kLate (a 1e-4 of the eye's distance) is a leak

struct Target {
    Float3 point;                      // a vertex, or the midpoint of an edge (rounded to float)
    std::vector<std::uint32_t> faces;  // the triangles around it
};

struct D3 {
    double x, y, z;
};
D3 d3(Float3 p) { return {p.x, p.y, p.z}; }
D3 sub(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dotd(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 crossd(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

// Vertices whose triangles close a fan around them (every link vertex used twice, no degenerate
// triangle) and edges shared by exactly two triangles in opposite directions.
std::vector<Target> closed_targets(const Scene& scene, std::size_t per_kind, unsigned seed) {
    const auto idx = scene.indices();
    const std::size_t n = scene.triangle_count();
    std::vector<std::vector<std::uint32_t>> around(scene.vertex_count());
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> edges;
    for (std::uint32_t t = 0; t < n; ++t) {
        if (scene.is_degenerate(t)) continue;
        for (int k = 0; k < 3; ++k) {
            around[idx[3 * t + k]].push_back(t);
            const std::uint32_t a = idx[3 * t + k], b = idx[3 * t + (k + 1) % 3];
            edges[{std::min(a, b), std::max(a, b)}].push_back(t);
        }
    }
    std::vector<Target> vertices, midpoints;
    for (std::uint32_t v = 0; v < around.size(); ++v) {
        if (around[v].size() < 3) continue;
        std::map<std::uint32_t, int> link;
        for (std::uint32_t t : around[v])
            for (int k = 0; k < 3; ++k)
                if (idx[3 * t + k] != v) ++link[idx[3 * t + k]];
        bool closed = link.size() == around[v].size();
        for (const auto& [w, count] : link) closed = closed && count == 2;
        if (closed) vertices.push_back(Target{scene.vertices()[v], around[v]});
    }
    for (const auto& [e, tris] : edges) {
        if (tris.size() != 2) continue;
        const Float3 a = scene.vertices()[e.first], b = scene.vertices()[e.second];
        midpoints.push_back(Target{(a + b) * 0.5f, tris});
    }
    std::mt19937 rng(seed);
    std::shuffle(vertices.begin(), vertices.end(), rng);
    std::shuffle(midpoints.begin(), midpoints.end(), rng);
    vertices.resize(std::min(vertices.size(), per_kind));
    midpoints.resize(std::min(midpoints.size(), per_kind));
    vertices.insert(vertices.end(), midpoints.begin(), midpoints.end());
    return vertices;
}

// Eyes all round the scene: the 6 axis directions, the 8 diagonals and 6 random ones, at twice the
// box's diagonal from its centre.
std::vector<Float3> eyes(const Box& b, unsigned seed) {
    std::vector<Float3> dirs;
    for (int k = 0; k < 3; ++k)
        for (float s : {1.0f, -1.0f}) {
            Float3 d{0, 0, 0};
            d[k] = s;
            dirs.push_back(d);
        }
    for (int i = 0; i < 8; ++i)
        dirs.push_back(Float3{(i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? 1.0f : -1.0f});
    std::mt19937 rng(seed);
    std::normal_distribution<float> g;
    for (int i = 0; i < 6; ++i) dirs.push_back(Float3{g(rng), g(rng), g(rng)});
    std::vector<Float3> out;
    for (const Float3& d : dirs) out.push_back(b.center() + normalize(d) * (2.0f * b.diagonal()));
    return out;
}

// The ray from `eye` to the target (t = 1 there) if it enters the surface there: for every face
// around the target, the direction points into the face's back side at more than 3 degrees.
bool entering_ray(const Scene& scene, const Target& target, Float3 eye, Ray& ray) {
    ray = Ray{eye, 0.0f, target.point - eye, kInfinity};
    const D3 d = d3(ray.dir);
    const double dl = std::sqrt(dotd(d, d));
    for (std::uint32_t t : target.faces) {
        const Triangle& tri = scene.triangle(t);
        const D3 n = crossd(sub(d3(tri.v1), d3(tri.v0)), sub(d3(tri.v2), d3(tri.v0)));
        if (!(dotd(d, n) < -0.05 * dl * std::sqrt(dotd(n, n)))) return false;
    }
    return true;
}

// Rays of one eye arranged as an image: rows of similar screen height, each sorted across, so that
// the 4x4 packets (and MLRTA's tiles) hold neighbouring rays.
workload::RaySet as_image(std::vector<Ray> rays, Float3 eye, Float3 centre, Mode mode) {
    scenes::Camera cam;
    cam.eye = eye;
    cam.at = centre;
    const scenes::Camera::Basis basis = cam.basis();
    auto sx = [&](const Ray& r) { return dot(r.dir, basis.right) / dot(r.dir, basis.forward); };
    auto sy = [&](const Ray& r) { return dot(r.dir, basis.up) / dot(r.dir, basis.forward); };
    const std::size_t side = std::max<std::size_t>(4, std::size_t(std::ceil(std::sqrt(double(rays.size())))));
    std::sort(rays.begin(), rays.end(), [&](const Ray& a, const Ray& b) { return sy(a) < sy(b); });
    for (std::size_t row = 0; row * side < rays.size(); ++row) {
        auto first = rays.begin() + std::ptrdiff_t(row * side);
        auto last = rays.begin() + std::ptrdiff_t(std::min(rays.size(), (row + 1) * side));
        std::sort(first, last, [&](const Ray& a, const Ray& b) { return sx(a) < sx(b); });
    }
    return image_ray_set(rays, int(side), mode);
}

struct LeakCount {
    std::uint64_t rays = 0, leaks = 0;
};

LeakCount count_leaks(const workload::RaySet& set, const std::vector<Hit>& hits) {
    LeakCount c;
    for (std::size_t slot = 0; slot < set.slots(); ++slot) {
        if (!set.active(slot)) continue;
        ++c.rays;
        c.leaks += !(hits[slot].hit() && hits[slot].t <= 1.0f + kLate);
    }
    return c;
}

LeakCount count_leaks(const workload::RaySet& set, const std::vector<std::uint8_t>& occluded) {
    LeakCount c;
    for (std::size_t slot = 0; slot < set.slots(); ++slot) {
        if (!set.active(slot)) continue;
        ++c.rays;
        c.leaks += occluded[slot] == 0;
    }
    return c;
}

void expect_watertight(const scenes::SceneSource& source, std::size_t per_kind) {
    const Scene& scene = source.scene;
    const std::vector<Target> targets = closed_targets(scene, per_kind, 1);
    ASSERT_GT(targets.size(), 0u) << source.name << " has no closed vertex or edge";
    EngineChoice choice;
    choice.brute = scene.triangle_count() <= 1100;  // every triangle for every ray: kept to tetra:4
    choice.vlf_fast = false;             // approximate by design: it misses hits wherever a ray leaves its first tile
    choice.options.vlf.directions = 33;  // few subfields to build: the rays of one eye share a handful
    choice.options.vlf.tiles = 64;
    const std::vector<EngineUnderTest> engines = build_engines(scene, choice);
    const oracle::EmbreeOracle embree(scene);
    std::map<std::string, LeakCount> leaks;
    std::uint64_t reference_rays = 0, reference_leaks = 0;
    for (const Float3& eye : eyes(scene.bounds(), 2)) {
        std::vector<Ray> rays;
        Ray r;
        for (const Target& t : targets)
            if (entering_ray(scene, t, eye, r)) rays.push_back(r);
        if (rays.empty()) continue;
        // The construction itself, checked with exact geometry (triangles grown by 1e-9, as double
        // precision alone is not watertight) on a sample of the rays.
        for (std::size_t i = 0; i < rays.size(); i += 97) {
            const Hit h = exact_intersect(scene, rays[i], 1e-9);
            ++reference_rays;
            reference_leaks += !(h.hit() && h.t <= 1.0f + kLate);
        }
        for (Mode mode : {Mode::primary, Mode::shadow}) {
            std::vector<Ray> segment = rays;
            if (mode == Mode::shadow)
                for (Ray& s : segment) s.tfar = 1.0f + kLate;
            const workload::RaySet set = as_image(segment, eye, scene.bounds().center(), mode);
            const std::string suffix = mode == Mode::primary ? " closest" : " occluded";
            for (const EngineUnderTest& e : engines) {
                LeakCount c;
                if (mode == Mode::primary) {
                    std::vector<Hit> hits;
                    e.engine->intersect(set, hits, 1);
                    c = count_leaks(set, hits);
                } else {
                    std::vector<std::uint8_t> occluded;
                    e.engine->occluded(set, occluded, 1);
                    c = count_leaks(set, occluded);
                }
                leaks[e.name + suffix].rays += c.rays;
                leaks[e.name + suffix].leaks += c.leaks;
            }
            LeakCount c;
            for (std::size_t slot = 0; slot < set.slots(); ++slot) {
                if (!set.active(slot)) continue;
                ++c.rays;
                const Ray ray = set.ray(slot);
                if (mode == Mode::primary) {
                    const Hit h = embree.intersect1(ray);
                    c.leaks += !(h.hit() && h.t <= 1.0f + kLate);
                } else {
                    c.leaks += !embree.occluded1(ray);
                }
            }
            leaks["embree" + suffix].rays += c.rays;
            leaks["embree" + suffix].leaks += c.leaks;
        }
    }
    std::printf("[%s] %zu closed targets; exact geometry: %llu leaks of %llu sampled rays\n", source.name.c_str(),
                targets.size(), (unsigned long long)reference_leaks, (unsigned long long)reference_rays);
    EXPECT_EQ(reference_leaks, 0u) << "the rays are not built as intended";
    for (const auto& [name, c] : leaks) {
        std::printf("[%s] %-18s leaks %llu of %llu rays\n", source.name.c_str(), name.c_str(),
                    (unsigned long long)c.leaks, (unsigned long long)c.rays);
        EXPECT_GT(c.rays, 0u) << name;
        if (name.rfind("embree", 0) != 0) {
            EXPECT_EQ(c.leaks, 0u) << source.name << ": " << name << " lets rays through the surface";
        }
    }
    std::fflush(stdout);
}

}  // namespace

TEST(Watertight, Bunny) {
    const std::string path = scene_path("bunny00.off", true);
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared scene not found: " << path;
    expect_watertight(scenes::load_scene(path), 2000);
}

TEST(Watertight, Tetra) { expect_watertight(scenes::load_scene("tetra:4"), 1000000); }

TEST(Watertight, Sphereflake) { expect_watertight(scenes::load_scene("sphereflake:1"), 2500); }

}  // namespace beamtrace::test
