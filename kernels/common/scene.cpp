// Scene: validation at the edge and the library's own copy of the triangles.
#include "beamtrace/scene.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "beamtrace/error.hpp"

namespace beamtrace {

struct Scene::Data {
    std::vector<Float3> vertices;
    std::vector<std::uint32_t> indices;
    std::vector<Triangle> triangles;
    std::vector<std::uint8_t> degenerate;
    std::size_t degenerate_count = 0;
    Box bounds;
};

namespace {

// Zero area in double precision: the cross product of two edges vanishes exactly.
bool zero_area(const Triangle& t) {
    const double ax = double(t.v1.x) - t.v0.x, ay = double(t.v1.y) - t.v0.y, az = double(t.v1.z) - t.v0.z;
    const double bx = double(t.v2.x) - t.v0.x, by = double(t.v2.y) - t.v0.y, bz = double(t.v2.z) - t.v0.z;
    const double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
    return cx == 0.0 && cy == 0.0 && cz == 0.0;
}

}  // namespace

Scene::Scene(std::span<const Float3> vertices, std::span<const std::uint32_t> indices)
    : Scene(vertices.empty() ? nullptr : &vertices[0].x, vertices.size(), indices.data(),
            indices.size() % 3 == 0
                ? indices.size() / 3
                : throw Error("scene: index count " + std::to_string(indices.size()) + " is not a multiple of 3")) {}

Scene::Scene(const float* xyz, std::size_t vertex_count, const std::uint32_t* idx, std::size_t triangle_count) {
    if (triangle_count == 0) throw Error("scene: empty scene (no triangles)");
    if (triangle_count > kMaxTriangles)
        throw Error("scene: " + std::to_string(triangle_count) + " triangles exceed the limit of 2^31");
    if (vertex_count == 0) throw Error("scene: no vertices");
    if (xyz == nullptr) throw Error("scene: vertex pointer is null");
    if (idx == nullptr) throw Error("scene: index pointer is null");
    if (vertex_count > std::size_t{0xFFFFFFFFu})
        throw Error("scene: " + std::to_string(vertex_count) + " vertices exceed the limit of 2^32");

    auto data = std::make_shared<Data>();
    data->vertices.resize(vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i) {
        const Float3 p{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
        for (int a = 0; a < 3; ++a) {
            if (!std::isfinite(p[a]))
                throw Error("scene: vertex " + std::to_string(i) + " has a " + (std::isnan(p[a]) ? "NaN" : "infinite") +
                            " coordinate (" + "xyz"[a] + ")");
        }
        data->vertices[i] = p;
    }
    data->indices.assign(idx, idx + 3 * triangle_count);
    data->triangles.resize(triangle_count);
    data->degenerate.assign(triangle_count, 0);
    for (std::size_t t = 0; t < triangle_count; ++t) {
        Float3 c[3];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = data->indices[3 * t + k];
            if (v >= vertex_count)
                throw Error("scene: triangle " + std::to_string(t) + " corner " + std::to_string(k) +
                            " has vertex index " + std::to_string(v) + ", out of range (vertex count " +
                            std::to_string(vertex_count) + ")");
            c[k] = data->vertices[v];
            data->bounds.extend(c[k]);
        }
        data->triangles[t] = Triangle{c[0], c[1], c[2]};
        if (zero_area(data->triangles[t])) {
            data->degenerate[t] = 1;
            ++data->degenerate_count;
        }
    }
    triangles_ = data->triangles.data();
    data_ = std::move(data);
}

std::size_t Scene::triangle_count() const { return data_->triangles.size(); }
std::size_t Scene::vertex_count() const { return data_->vertices.size(); }
std::size_t Scene::degenerate_count() const { return data_->degenerate_count; }
bool Scene::is_degenerate(std::uint32_t t) const { return data_->degenerate[t] != 0; }
std::span<const Triangle> Scene::triangles() const { return data_->triangles; }
std::span<const Float3> Scene::vertices() const { return data_->vertices; }
std::span<const std::uint32_t> Scene::indices() const { return data_->indices; }
const Box& Scene::bounds() const { return data_->bounds; }
std::size_t Scene::memory_bytes() const {
    return data_->vertices.size() * sizeof(Float3) + data_->indices.size() * sizeof(std::uint32_t) +
           data_->triangles.size() * sizeof(Triangle) + data_->degenerate.size();
}

}  // namespace beamtrace
