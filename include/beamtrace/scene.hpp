#pragma once
// A triangle scene in the library's own layout, built from caller-owned arrays.
//
// The constructor validates everything once (this is where data enters the library) and copies it:
// afterwards the caller's arrays may be freed. A Scene is an immutable, cheaply copyable handle
// (shared ownership), so acceleration structures built from it keep it alive.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "beamtrace/vec.hpp"

namespace beamtrace {

// The three corners of one triangle, stored contiguously (36 bytes) so that a leaf test touches one
// cache line or two per triangle.
struct Triangle {
    Float3 v0, v1, v2;
};

class Scene {
public:
    // Largest number of triangles a scene may hold (triangle ids are 31-bit).
    static constexpr std::size_t kMaxTriangles = std::size_t{1} << 31;

    // vertices: vertex_count points as x,y,z floats. indices: 3 * triangle_count vertex indices.
    // Throws beamtrace::Error naming the problem and the offending index for: an empty scene, more
    // than kMaxTriangles triangles, a NaN or infinite coordinate, an index out of range, null pointers.
    Scene(const float* vertices_xyz, std::size_t vertex_count, const std::uint32_t* indices,
          std::size_t triangle_count);
    Scene(std::span<const Float3> vertices, std::span<const std::uint32_t> indices);

    std::size_t triangle_count() const;
    std::size_t vertex_count() const;
    // Triangles of zero area (repeated or collinear corners, evaluated in double precision). They are
    // kept, so triangle ids stay the caller's, but no query can ever hit them.
    std::size_t degenerate_count() const;
    bool is_degenerate(std::uint32_t triangle) const;

    const Triangle& triangle(std::uint32_t id) const { return triangles_[id]; }
    std::span<const Triangle> triangles() const;
    // The caller's vertices and indices as copied (for exporting the scene to other ray tracers).
    std::span<const Float3> vertices() const;
    std::span<const std::uint32_t> indices() const;
    const Box& bounds() const;
    // Bytes held by the scene's arrays.
    std::size_t memory_bytes() const;

private:
    struct Data;
    std::shared_ptr<const Data> data_;
    const Triangle* triangles_ = nullptr;  // == data_->triangles.data(), cached for the hot path
};

}  // namespace beamtrace
