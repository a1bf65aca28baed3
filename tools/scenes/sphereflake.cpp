// "sphereflake:LEVEL": Haines' sphereflake (Standard Procedural Databases). A sphere carries 9 child
// spheres of a third of its radius touching its surface, 6 round its "equator" and 3 above them; each
// child does the same about the direction it grew in, LEVEL generations deep. There are
// (9^(LEVEL+1) - 1) / 8 spheres: 1, 10, 91, 820, 7381, 66430.
//
// Every sphere is a closed subdivided icosahedron (shared vertices, no seams). Big spheres get more
// triangles than small ones, as a renderer would want: 1280 for the root, 320 for generations 1-3,
// 80 below, which keeps level 5 at 5.5 million triangles instead of 21 million.
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "beamtrace/error.hpp"
#include "scenes/generators.hpp"
#include "scenes/mesh_builder.hpp"

namespace beamtrace::scenes {

namespace {

int subdivisions_for_generation(int generation) { return generation == 0 ? 3 : generation <= 3 ? 2 : 1; }

// Directions of the 9 children in the frame of their parent (+y = the parent's growth direction).
std::array<Float3, 9> child_directions() {
    constexpr float pi = std::numbers::pi_v<float>;
    std::array<Float3, 9> d{};
    for (int k = 0; k < 6; ++k) {  // the equator ring, 60 degrees apart
        const float a = pi / 3.0f * static_cast<float>(k);
        d[k] = {std::cos(a), 0.0f, std::sin(a)};
    }
    const float elevation = 55.0f * pi / 180.0f;  // the upper trio, between the ring's gaps
    for (int k = 0; k < 3; ++k) {
        const float a = pi / 6.0f + 2.0f * pi / 3.0f * static_cast<float>(k);
        d[6 + k] = {std::cos(elevation) * std::cos(a), std::sin(elevation), std::cos(elevation) * std::sin(a)};
    }
    return d;
}

struct Flake {
    std::array<MeshBuilder, 4> spheres;  // unit icospheres by subdivision count
    std::array<Float3, 9> directions = child_directions();
    int levels = 0;
    MeshBuilder mesh;

    // `orientation` is a rotation whose +y axis is the direction this sphere grew in.
    void grow(Float3 centre, float radius, const Frame& orientation, int generation) {
        mesh.begin_object();  // each sphere is one object
        mesh.append(spheres[subdivisions_for_generation(generation)], Frame::upright(centre, 0.0f, radius));
        if (generation == levels) return;
        const float child_radius = radius / 3.0f;
        for (const Float3& local : directions) {
            const Float3 d = orientation.vector(local);
            grow(centre + d * (radius + child_radius), child_radius, Frame::along({0, 0, 0}, d), generation + 1);
        }
    }
};

}  // namespace

SceneSource sphereflake(int level) {
    if (level < 0 || level > kMaxSphereflakeLevel)
        throw Error("sphereflake: level " + std::to_string(level) + " must be between 0 and " +
                    std::to_string(kMaxSphereflakeLevel));
    Flake flake;
    flake.levels = level;
    for (int s = 1; s <= 3; ++s) flake.spheres[s] = unit_icosphere(s);
    std::size_t spheres = 0, triangles = 0, vertices = 0, generation_size = 1;
    for (int g = 0; g <= level; ++g, generation_size *= 9) {
        const MeshBuilder& unit = flake.spheres[subdivisions_for_generation(g)];
        spheres += generation_size;
        triangles += generation_size * unit.triangle_count();
        vertices += generation_size * unit.vertex_count();
    }
    flake.mesh.reserve(vertices, triangles);
    flake.grow({0, 0, 0}, 1.0f, Frame{}, 0);
    Scene scene = flake.mesh.build();
    Camera camera = frame_from_outside(scene.bounds());
    return SceneSource{"sphereflake:" + std::to_string(level), std::move(scene), camera,
                       "sphereflake (Haines SPD), level " + std::to_string(level) + ": " + std::to_string(spheres) +
                           " closed tessellated spheres",
                       flake.mesh.object_of_triangle()};
}

}  // namespace beamtrace::scenes
