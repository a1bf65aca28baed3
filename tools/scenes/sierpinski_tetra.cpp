// "tetra:LEVEL": the Sierpinski tetrahedron of Haines' Standard Procedural Databases. A tetrahedron
// is replaced by the four half-size tetrahedra at its corners, LEVEL times: 4^LEVEL tetrahedra, each a
// closed mesh of 4 vertices and 4 triangles.
//
// Neighbouring tetrahedra touch at single points. Every corner is computed from integer lattice
// coordinates (i, j, k) in units of 1/2^LEVEL of the base edges, in double precision, so a touching
// point is bit-identical in both tetrahedra that share it: no crack for a ray to slip through.
#include <algorithm>
#include <cmath>
#include <string>

#include "beamtrace/error.hpp"
#include "scenes/generators.hpp"
#include "scenes/mesh_builder.hpp"

namespace beamtrace::scenes {

namespace {

struct Lattice {
    // The base tetrahedron: a regular one with edge 2, standing on a face in the y = 0 plane.
    double origin[3], edge[3][3];
    double step;  // 1 / 2^level

    Float3 point(std::int64_t i, std::int64_t j, std::int64_t k) const {
        Float3 p;
        for (int a = 0; a < 3; ++a)
            p[a] = static_cast<float>(origin[a] + step * (static_cast<double>(i) * edge[0][a] +
                                                          static_cast<double>(j) * edge[1][a] +
                                                          static_cast<double>(k) * edge[2][a]));
        return p;
    }
};

// Objects (SceneSource::object_of_triangle): the tetrahedra of one subdivision `kObjectLevels` levels
// above the smallest, 16 of them (64 triangles) each; the whole scene below level 2.
constexpr int kObjectLevels = 2;

void subdivide(MeshBuilder& mesh, const Lattice& lattice, std::int64_t i, std::int64_t j, std::int64_t k,
               std::int64_t size, int levels_left, int object_levels) {
    if (levels_left == object_levels) mesh.begin_object();
    if (levels_left == 0) {
        mesh.add_tetrahedron(lattice.point(i, j, k), lattice.point(i + size, j, k), lattice.point(i, j + size, k),
                             lattice.point(i, j, k + size));
        return;
    }
    const std::int64_t half = size / 2;
    subdivide(mesh, lattice, i, j, k, half, levels_left - 1, object_levels);
    subdivide(mesh, lattice, i + half, j, k, half, levels_left - 1, object_levels);
    subdivide(mesh, lattice, i, j + half, k, half, levels_left - 1, object_levels);
    subdivide(mesh, lattice, i, j, k + half, half, levels_left - 1, object_levels);
}

}  // namespace

SceneSource sierpinski_tetra(int level) {
    if (level < 0 || level > kMaxTetraLevel)
        throw Error("tetra: level " + std::to_string(level) + " must be between 0 and " +
                    std::to_string(kMaxTetraLevel));
    const double r = 2.0 / std::sqrt(3.0);  // circumradius of the base triangle (edge 2)
    const double height = 2.0 * std::sqrt(2.0 / 3.0);
    const double pi = std::acos(-1.0);
    double base[3][3];
    for (int c = 0; c < 3; ++c) {
        const double a = pi / 2.0 + 2.0 * pi * c / 3.0;
        base[c][0] = r * std::cos(a);
        base[c][1] = 0.0;
        base[c][2] = r * std::sin(a);
    }
    Lattice lattice{};
    for (int a = 0; a < 3; ++a) {
        lattice.origin[a] = base[0][a];
        lattice.edge[0][a] = base[1][a] - base[0][a];
        lattice.edge[1][a] = base[2][a] - base[0][a];
        lattice.edge[2][a] = (a == 1 ? height : 0.0) - base[0][a];  // towards the apex above the centre
    }
    const std::int64_t size = std::int64_t{1} << level;
    lattice.step = 1.0 / static_cast<double>(size);

    const std::size_t tetrahedra = std::size_t{1} << (2 * level);
    MeshBuilder mesh;
    mesh.reserve(4 * tetrahedra, 4 * tetrahedra);
    subdivide(mesh, lattice, 0, 0, 0, size, level, std::min(level, kObjectLevels));
    Scene scene = mesh.build();
    Camera camera = frame_from_outside(scene.bounds());
    return SceneSource{"tetra:" + std::to_string(level), std::move(scene), camera,
                       "Sierpinski tetrahedron (Haines SPD), level " + std::to_string(level) + ": " +
                           std::to_string(tetrahedra) + " closed tetrahedra",
                       mesh.object_of_triangle()};
}

}  // namespace beamtrace::scenes
