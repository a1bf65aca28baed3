#pragma once
// The state of a Crsh (crsh.hpp): the scene's non-degenerate triangles in object order with their
// bounding spheres (structure of arrays, what the sphere-cone tests read), and the objects' ranges
// and spheres. Nothing here depends on rays: every call builds its own ray hierarchy.
#include <cstdint>
#include <span>
#include <vector>

#include "beamtrace/crsh.hpp"
#include "common/triangle_kernels.hpp"
#include "crsh/bounding_spheres.hpp"

namespace beamtrace {

struct Crsh::Impl {
    explicit Impl(const Scene& s) : scene(s) {}
    Scene scene;
    const TriangleKernels* kernels = nullptr;
    std::vector<Triangle> triangles;                            // non-degenerate, object by object
    std::vector<std::uint32_t> ids;                             // the caller's id of each
    std::vector<float> sphere_x, sphere_y, sphere_z, sphere_r;  // each one's bounding sphere
    std::vector<std::uint32_t> object_first;                    // object o: [object_first[o], object_first[o + 1])
    std::vector<crsh::Sphere> object_spheres;
    CrshStats stats;

    std::size_t object_count() const { return object_spheres.size(); }
};

namespace crsh {
// Groups the scene's non-degenerate triangles by object (objects by ascending id, triangles by
// ascending id within one; an empty partition makes one object) and computes every sphere. Throws
// beamtrace::Error when the partition's size is not the triangle count.
Crsh::Impl make_impl(const Scene& scene, std::span<const std::uint32_t> object_of_triangle);
}  // namespace crsh

}  // namespace beamtrace
