// "random:N": small random triangles spread uniformly through the unit cube, the scalability scene of
// VLF-RT (Mortensen et al., "A Visibility Field for Ray Tracing", CGIV 2007, section 6.1 and Figure 4:
// "uniformly distributed random triangles").
//
// The paper gives no triangle size. Triangles whose three corners are anywhere in the cube would make
// even a few thousand of them an opaque wall, so, as its pictures suggest, each triangle is small: a
// centre uniform in the cube, and three corners uniform within +-h of it on each axis, with
//     h = 0.2 / cbrt(N)      (0.4x the mean spacing 1/cbrt(N) of the centres along each axis).
// The depth complexity (the mean number of triangles an axis-parallel ray crosses through the whole
// cube, measured) then grows like cbrt(N): 0.13 for N = 1k, 0.26 for 10k, 1.2 for 1M (where about 30%
// of such rays still see through) and 2.6 for 10M. Centres are kept h away from the faces so every
// corner lies in [0,1]^3. Corners are independent (a triangle soup: nothing is shared).
#include <cmath>
#include <string>

#include "beamtrace/error.hpp"
#include "scenes/deterministic_random.hpp"
#include "scenes/generators.hpp"
#include "scenes/mesh_builder.hpp"

namespace beamtrace::scenes {

float random_triangle_half_size(std::size_t count) { return 0.2f / std::cbrt(static_cast<float>(count)); }

SceneSource random_triangles(std::size_t count, std::uint32_t seed) {
    if (count < 1 || count > kMaxRandomTriangles)
        throw Error("random: triangle count " + std::to_string(count) + " must be between 1 and " +
                    std::to_string(kMaxRandomTriangles));
    const float h = random_triangle_half_size(count);
    DeterministicRandom random(seed);
    MeshBuilder mesh;
    mesh.reserve(3 * count, count);
    for (std::size_t i = 0; i < count; ++i) {
        const Float3 centre{random.uniform(h, 1.0f - h), random.uniform(h, 1.0f - h), random.uniform(h, 1.0f - h)};
        Float3 corner[3];
        for (Float3& c : corner) {
            c = centre + Float3{random.uniform(-h, h), random.uniform(-h, h), random.uniform(-h, h)};
            c = min(max(c, Float3{0, 0, 0}), Float3{1, 1, 1});  // rounding must not step outside the cube
        }
        mesh.add_triangle(corner[0], corner[1], corner[2]);
    }
    Scene scene = mesh.build();
    Camera camera = frame_from_outside(Box{{0, 0, 0}, {1, 1, 1}});
    return SceneSource{"random:" + std::to_string(count), std::move(scene), camera,
                       std::to_string(count) + " random triangles of half-size " + std::to_string(h) +
                           " in the unit cube (VLF-RT 6.1), seed " + std::to_string(seed)};
}

}  // namespace beamtrace::scenes
