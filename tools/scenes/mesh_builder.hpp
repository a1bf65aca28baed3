#pragma once
// MeshBuilder: the one place where procedural geometry is turned into vertices and triangles. Every
// generator (tetra, sphereflake, room, random) writes through it, so each shape is written once.
//
// Conventions, relied on by the tests:
//  - Closed shapes (box, tetrahedron, spheres, lathes, tori, tubes) are closed 2-manifolds with shared
//    vertices: every edge belongs to exactly two triangles, once in each direction.
//  - Triangles are counter-clockwise seen from outside: cross(v1 - v0, v2 - v0) points out of the
//    solid, so a closed shape has positive signed volume (Facing::inward flips this for a box).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "beamtrace/scene.hpp"
#include "beamtrace/vec.hpp"

namespace beamtrace::scenes {

// A placement of local coordinates: local point p goes to origin + x * p.x + y * p.y + z * p.z. The
// axes carry rotation and scale; a right-handed frame (positive determinant) keeps orientation.
struct Frame {
    Float3 origin{0, 0, 0};
    Float3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};

    Float3 point(Float3 p) const { return origin + x * p.x + y * p.y + z * p.z; }
    Float3 vector(Float3 v) const { return x * v.x + y * v.y + z * v.z; }

    // Uniform scale, then a turn of yaw_radians about the vertical (+y) axis, then a move to origin.
    static Frame upright(Float3 origin, float yaw_radians = 0.0f, float scale = 1.0f);
    // Local +y along `axis` (any length, not zero), uniform scale, moved to origin.
    static Frame along(Float3 origin, Float3 axis, float scale = 1.0f);
    // Scale by (sx, sy, sz) along the local axes: the frame of an ellipsoid or a squashed shape.
    Frame scaled(float sx, float sy, float sz) const { return Frame{origin, x * sx, y * sy, z * sz}; }
    // The frame that applies `inner` first, then this one.
    Frame operator*(const Frame& inner) const {
        return Frame{point(inner.origin), vector(inner.x), vector(inner.y), vector(inner.z)};
    }
};

// One point of a lathe profile: distance from the axis and height along it.
struct ProfilePoint {
    float r = 0.0f;
    float y = 0.0f;
};

enum class Facing { outward, inward };

class MeshBuilder {
public:
    void reserve(std::size_t vertices, std::size_t triangles);

    std::uint32_t add_vertex(Float3 p);
    void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c);
    // A free-standing triangle with three vertices of its own (triangle soup, for random scenes).
    void add_triangle(Float3 a, Float3 b, Float3 c);
    // Two triangles (a, b, c) and (a, c, d); a..d counter-clockwise seen from the front.
    void add_quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d);

    // Closed axis-aligned box: 8 vertices, 12 triangles. Facing::inward turns it into a room shell.
    void add_box(const Box& box, Facing facing = Facing::outward);
    // Closed tetrahedron: 4 vertices, 4 triangles, facing away from the opposite corner.
    void add_tetrahedron(Float3 a, Float3 b, Float3 c, Float3 d);
    // Sphere made of an icosahedron whose faces are split `subdivisions` times (20 * 4^s triangles).
    void add_tessellated_sphere(Float3 centre, float radius, int subdivisions);
    // Surface of revolution about the frame's +y axis. profile.front() and profile.back() must lie on
    // the axis (r == 0, they become the two poles), the points between off it (r > 0), ordered from
    // bottom to top going round the solid counter-clockwise in the (r, y) plane. 2 * segments *
    // (profile.size() - 2) triangles.
    void add_lathe(const Frame& frame, std::span<const ProfilePoint> profile, int segments);
    // Unit-radius sphere as a lathe (rings >= 2 latitude bands): an ellipsoid when the frame is scaled.
    void add_uv_sphere(const Frame& frame, int segments, int rings);
    // Closed tube of circular cross-section along the closed polyline `curve` (in frame coordinates,
    // at least 3 points, last joined back to first). 2 * curve.size() * sides triangles.
    void add_tube(const Frame& frame, std::span<const Float3> curve, float radius, int sides);
    // Torus about the frame's +y axis: a tube along a circle. 2 * major_segments * minor_segments.
    void add_torus(const Frame& frame, float major_radius, float minor_radius, int major_segments, int minor_segments);

    // Copy another mesh in, placed by `frame` (instancing a template such as a tessellated sphere).
    void append(const MeshBuilder& mesh, const Frame& frame);

    // Objects (the optional partition of SceneSource::object_of_triangle): the triangles added from now
    // on belong to a new object, until the next call (a call right after another, with no triangle
    // between, begins nothing new).
    void begin_object();
    // Per triangle, its object, numbered in the order begun (triangles added before the first call, if
    // any, are object 0). Empty when begin_object was never called.
    std::vector<std::uint32_t> object_of_triangle() const;

    std::size_t vertex_count() const { return vertices_.size(); }
    std::size_t triangle_count() const { return indices_.size() / 3; }
    std::span<const Float3> vertices() const { return vertices_; }
    std::span<const std::uint32_t> indices() const { return indices_; }

    // The validated library scene (throws beamtrace::Error as Scene does, e.g. when empty).
    Scene build() const;

private:
    std::vector<Float3> vertices_;
    std::vector<std::uint32_t> indices_;
    std::vector<std::size_t> object_starts_;  // first triangle of each object begun
};

// Unit sphere about the origin from a subdivided icosahedron, vertices shared: 20 * 4^s triangles.
MeshBuilder unit_icosphere(int subdivisions);

}  // namespace beamtrace::scenes
