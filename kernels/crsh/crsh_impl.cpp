#include "crsh/crsh_impl.hpp"

#include <algorithm>
#include <chrono>
#include <string>

#include "beamtrace/error.hpp"

namespace beamtrace::crsh {

Crsh::Impl make_impl(const Scene& scene, std::span<const std::uint32_t> object_of_triangle) {
    const auto start = std::chrono::steady_clock::now();
    const std::size_t n = scene.triangle_count();
    if (!object_of_triangle.empty() && object_of_triangle.size() != n)
        throw Error("Crsh: the object partition has " + std::to_string(object_of_triangle.size()) +
                    " entries but the scene has " + std::to_string(n) + " triangles (one object id per triangle)");
    Crsh::Impl impl(scene);
    impl.kernels = &triangle_kernels();

    // (object, triangle) of every non-degenerate triangle, sorted: objects by id, triangles by id.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> order;
    order.reserve(n);
    for (std::uint32_t t = 0; t < n; ++t)
        if (!scene.is_degenerate(t)) order.emplace_back(object_of_triangle.empty() ? 0u : object_of_triangle[t], t);
    std::sort(order.begin(), order.end());

    const std::size_t m = order.size();
    impl.triangles.resize(m);
    impl.ids.resize(m);
    impl.sphere_x.resize(m);
    impl.sphere_y.resize(m);
    impl.sphere_z.resize(m);
    impl.sphere_r.resize(m);
    for (std::size_t k = 0; k < m; ++k) {
        const std::uint32_t t = order[k].second;
        impl.triangles[k] = scene.triangle(t);
        impl.ids[k] = t;
        const Sphere s = triangle_sphere(impl.triangles[k]);
        impl.sphere_x[k] = s.centre.x;
        impl.sphere_y[k] = s.centre.y;
        impl.sphere_z[k] = s.centre.z;
        impl.sphere_r[k] = s.radius;
        if (k == 0 || order[k].first != order[k - 1].first) impl.object_first.push_back(static_cast<std::uint32_t>(k));
    }
    impl.object_first.push_back(static_cast<std::uint32_t>(m));
    const std::size_t objects = impl.object_first.size() - 1;
    impl.object_spheres.resize(objects);
    std::size_t largest = 0;
    for (std::size_t o = 0; o < objects; ++o) {
        const std::size_t b = impl.object_first[o], e = impl.object_first[o + 1];
        impl.object_spheres[o] = bounding_sphere(std::span<const Triangle>(impl.triangles.data() + b, e - b));
        largest = std::max(largest, e - b);
    }

    CrshStats& s = impl.stats;
    s.triangles = n;
    s.degenerate_triangles = n - m;
    s.objects = objects;
    s.largest_object = largest;
    s.memory_bytes = m * (sizeof(Triangle) + sizeof(std::uint32_t) + 4 * sizeof(float)) +
                     objects * (sizeof(Sphere) + sizeof(std::uint32_t));
    s.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return impl;
}

}  // namespace beamtrace::crsh
