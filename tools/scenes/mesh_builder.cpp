// MeshBuilder: closed primitives with shared vertices, all counter-clockwise seen from outside.
#include "scenes/mesh_builder.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <unordered_map>

#include "beamtrace/error.hpp"

namespace beamtrace::scenes {

namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

// Any unit vector perpendicular to the unit vector n.
Float3 perpendicular(Float3 n) {
    const Float3 helper = std::fabs(n.x) < 0.9f ? Float3{1, 0, 0} : Float3{0, 1, 0};
    return normalize(cross(n, helper));
}

}  // namespace

Frame Frame::upright(Float3 origin, float yaw_radians, float scale) {
    const float c = std::cos(yaw_radians) * scale, s = std::sin(yaw_radians) * scale;
    return Frame{origin, {c, 0, -s}, {0, scale, 0}, {s, 0, c}};
}

Frame Frame::along(Float3 origin, Float3 axis, float scale) {
    const Float3 y = normalize(axis);
    const Float3 x = perpendicular(y);
    const Float3 z = cross(x, y);
    return Frame{origin, x * scale, y * scale, z * scale};
}

void MeshBuilder::reserve(std::size_t vertices, std::size_t triangles) {
    vertices_.reserve(vertices);
    indices_.reserve(3 * triangles);
}

std::uint32_t MeshBuilder::add_vertex(Float3 p) {
    if (vertices_.size() >= std::size_t{0xFFFFFFFFu}) throw Error("mesh builder: more than 2^32 vertices");
    vertices_.push_back(p);
    return static_cast<std::uint32_t>(vertices_.size() - 1);
}

void MeshBuilder::add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    indices_.push_back(a);
    indices_.push_back(b);
    indices_.push_back(c);
}

void MeshBuilder::add_triangle(Float3 a, Float3 b, Float3 c) {
    const std::uint32_t i = add_vertex(a);
    add_vertex(b);
    add_vertex(c);
    add_triangle(i, i + 1, i + 2);
}

void MeshBuilder::add_quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    add_triangle(a, b, c);
    add_triangle(a, c, d);
}

void MeshBuilder::add_box(const Box& box, Facing facing) {
    // Corner k has bit 0 -> upper x, bit 1 -> upper y, bit 2 -> upper z.
    const std::uint32_t base = static_cast<std::uint32_t>(vertices_.size());
    for (int k = 0; k < 8; ++k)
        add_vertex({(k & 1) ? box.upper.x : box.lower.x, (k & 2) ? box.upper.y : box.lower.y,
                    (k & 4) ? box.upper.z : box.lower.z});
    for (int axis = 0; axis < 3; ++axis) {
        const int u = 1 << ((axis + 1) % 3), v = 1 << ((axis + 2) % 3);  // bits of the other two axes
        for (int side = 0; side < 2; ++side) {
            const int s = side ? (1 << axis) : 0;
            // s, s+u, s+u+v, s+v turns counter-clockwise about +axis (u, v follow axis cyclically).
            std::array<std::uint32_t, 4> q{base + s, base + s + u, base + s + u + v, base + s + v};
            const bool outward_is_plus = side == 1;
            if (outward_is_plus != (facing == Facing::outward)) std::swap(q[1], q[3]);
            add_quad(q[0], q[1], q[2], q[3]);
        }
    }
}

void MeshBuilder::add_tetrahedron(Float3 a, Float3 b, Float3 c, Float3 d) {
    const std::array<Float3, 4> p{a, b, c, d};
    const std::uint32_t base = static_cast<std::uint32_t>(vertices_.size());
    for (const Float3& q : p) add_vertex(q);
    // Each face leaves out one corner; orient it away from that corner.
    for (std::uint32_t skip = 0; skip < 4; ++skip) {
        std::array<std::uint32_t, 3> f{};
        int n = 0;
        for (std::uint32_t k = 0; k < 4; ++k)
            if (k != skip) f[n++] = k;
        const Float3 normal = cross(p[f[1]] - p[f[0]], p[f[2]] - p[f[0]]);
        if (dot(normal, p[skip] - p[f[0]]) > 0.0f) std::swap(f[1], f[2]);
        add_triangle(base + f[0], base + f[1], base + f[2]);
    }
}

MeshBuilder unit_icosphere(int subdivisions) {
    if (subdivisions < 0 || subdivisions > 8)
        throw Error("icosphere: subdivisions " + std::to_string(subdivisions) + " outside 0..8");
    // The 12 corners of an icosahedron are the cyclic permutations of (0, +-1, +-phi); its 20 faces
    // are the triples of corners at mutual distance 2 (the edge length), oriented outward.
    const float phi = std::numbers::phi_v<float>;
    std::vector<Float3> corners;
    for (int axis = 0; axis < 3; ++axis)
        for (float s1 : {-1.0f, 1.0f})
            for (float s2 : {-phi, phi}) {
                Float3 p{0, 0, 0};
                p[(axis + 1) % 3] = s1;
                p[(axis + 2) % 3] = s2;
                corners.push_back(normalize(p));
            }
    MeshBuilder mesh;
    for (const Float3& c : corners) mesh.add_vertex(c);
    const float edge_length = 2.0f / std::sqrt(1.0f + phi * phi);  // normalised edge length
    auto is_edge = [&](int i, int j) { return std::fabs(length(corners[i] - corners[j]) - edge_length) < 1e-3f; };
    for (int i = 0; i < 12; ++i)
        for (int j = i + 1; j < 12; ++j)
            for (int k = j + 1; k < 12; ++k) {
                if (!is_edge(i, j) || !is_edge(j, k) || !is_edge(i, k)) continue;
                const Float3 n = cross(corners[j] - corners[i], corners[k] - corners[i]);
                if (dot(n, corners[i]) > 0.0f)
                    mesh.add_triangle(i, j, k);
                else
                    mesh.add_triangle(i, k, j);
            }

    for (int level = 0; level < subdivisions; ++level) {
        // Split every triangle into four; the midpoint of an edge is made once and shared.
        MeshBuilder finer;
        for (const Float3& p : mesh.vertices()) finer.add_vertex(p);
        std::unordered_map<std::uint64_t, std::uint32_t> midpoint;
        auto middle = [&](std::uint32_t a, std::uint32_t b) {
            const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
            auto [it, inserted] = midpoint.try_emplace(key, 0u);
            if (inserted) it->second = finer.add_vertex(normalize(finer.vertices()[a] + finer.vertices()[b]));
            return it->second;
        };
        for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
            const std::span<const std::uint32_t> corner = mesh.indices().subspan(3 * t, 3);
            const std::uint32_t a = corner[0], b = corner[1], c = corner[2];
            const std::uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
            finer.add_triangle(a, ab, ca);
            finer.add_triangle(ab, b, bc);
            finer.add_triangle(ca, bc, c);
            finer.add_triangle(ab, bc, ca);
        }
        mesh = std::move(finer);
    }
    return mesh;
}

void MeshBuilder::add_tessellated_sphere(Float3 centre, float radius, int subdivisions) {
    append(unit_icosphere(subdivisions), Frame::upright(centre, 0.0f, radius));
}

void MeshBuilder::add_lathe(const Frame& frame, std::span<const ProfilePoint> profile, int segments) {
    if (profile.size() < 3 || segments < 3 || profile.front().r != 0.0f || profile.back().r != 0.0f)
        throw Error("lathe: need >= 3 segments and a profile of >= 3 points starting and ending on the axis");
    for (std::size_t i = 1; i + 1 < profile.size(); ++i)
        if (!(profile[i].r > 0.0f)) throw Error("lathe: inner profile point " + std::to_string(i) + " on the axis");
    const std::uint32_t bottom = add_vertex(frame.point({0, profile.front().y, 0}));
    const std::uint32_t first_ring = static_cast<std::uint32_t>(vertices_.size());
    const std::uint32_t rings = static_cast<std::uint32_t>(profile.size() - 2);
    const std::uint32_t n = static_cast<std::uint32_t>(segments);
    for (std::uint32_t i = 0; i < rings; ++i) {
        const ProfilePoint p = profile[i + 1];
        for (std::uint32_t j = 0; j < n; ++j) {
            const float a = kTwoPi * static_cast<float>(j) / static_cast<float>(n);
            add_vertex(frame.point({p.r * std::cos(a), p.y, p.r * std::sin(a)}));
        }
    }
    const std::uint32_t top = add_vertex(frame.point({0, profile.back().y, 0}));
    auto ring = [&](std::uint32_t i, std::uint32_t j) { return first_ring + i * n + j % n; };
    for (std::uint32_t j = 0; j < n; ++j) {
        // Going up the profile then round the axis (+angle) is counter-clockwise seen from outside.
        add_triangle(ring(0, j), ring(0, j + 1), bottom);
        for (std::uint32_t i = 0; i + 1 < rings; ++i)
            add_quad(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1));
        add_triangle(ring(rings - 1, j), top, ring(rings - 1, j + 1));
    }
}

void MeshBuilder::add_uv_sphere(const Frame& frame, int segments, int rings) {
    if (rings < 2) throw Error("uv sphere: need at least 2 rings");
    std::vector<ProfilePoint> profile(static_cast<std::size_t>(rings) + 1);
    for (int i = 0; i <= rings; ++i) {
        const float polar = std::numbers::pi_v<float> * static_cast<float>(i) / static_cast<float>(rings);
        profile[i] = {i == 0 || i == rings ? 0.0f : std::sin(polar), -std::cos(polar)};
    }
    add_lathe(frame, profile, segments);
}

void MeshBuilder::add_tube(const Frame& frame, std::span<const Float3> curve, float radius, int sides) {
    const std::size_t m = curve.size();
    if (m < 3 || sides < 3) throw Error("tube: need a closed curve of >= 3 points and >= 3 sides");
    // Frames along the curve by parallel transport; the twist left over after one round is spread
    // evenly so the last ring meets the first one without a jump.
    std::vector<Float3> t(m), n(m);
    for (std::size_t k = 0; k < m; ++k) t[k] = normalize(curve[(k + 1) % m] - curve[(k + m - 1) % m]);
    // Carry a normal from one point to the next by removing its component along the new tangent.
    auto transport = [](Float3 normal, Float3 tangent) { return normalize(normal - tangent * dot(normal, tangent)); };
    n[0] = perpendicular(t[0]);
    for (std::size_t k = 1; k < m; ++k) n[k] = transport(n[k - 1], t[k]);
    const Float3 back_at_start = transport(n[m - 1], t[0]);
    const float twist = std::atan2(dot(cross(back_at_start, n[0]), t[0]), dot(back_at_start, n[0]));
    for (std::size_t k = 1; k < m; ++k) {
        const float angle = twist * static_cast<float>(k) / static_cast<float>(m);
        n[k] = n[k] * std::cos(angle) + cross(t[k], n[k]) * std::sin(angle);
    }
    const std::uint32_t base = static_cast<std::uint32_t>(vertices_.size());
    const std::uint32_t s = static_cast<std::uint32_t>(sides);
    for (std::size_t k = 0; k < m; ++k) {
        const Float3 b = cross(t[k], n[k]);  // n x b = t: the ring turns counter-clockwise about t
        for (std::uint32_t j = 0; j < s; ++j) {
            const float a = kTwoPi * static_cast<float>(j) / static_cast<float>(s);
            add_vertex(frame.point(curve[k] + (n[k] * std::cos(a) + b * std::sin(a)) * radius));
        }
    }
    const std::uint32_t rings = static_cast<std::uint32_t>(m);
    auto at = [&](std::uint32_t k, std::uint32_t j) { return base + (k % rings) * s + j % s; };
    for (std::uint32_t k = 0; k < rings; ++k)
        for (std::uint32_t j = 0; j < s; ++j) add_quad(at(k, j), at(k, j + 1), at(k + 1, j + 1), at(k + 1, j));
}

void MeshBuilder::add_torus(const Frame& frame, float major_radius, float minor_radius, int major_segments,
                            int minor_segments) {
    if (major_segments < 3) throw Error("torus: need at least 3 major segments");
    std::vector<Float3> circle(static_cast<std::size_t>(major_segments));
    for (int k = 0; k < major_segments; ++k) {
        const float a = kTwoPi * static_cast<float>(k) / static_cast<float>(major_segments);
        circle[k] = {major_radius * std::cos(a), 0.0f, major_radius * std::sin(a)};
    }
    add_tube(frame, circle, minor_radius, minor_segments);
}

void MeshBuilder::append(const MeshBuilder& mesh, const Frame& frame) {
    const std::uint32_t base = static_cast<std::uint32_t>(vertices_.size());
    if (vertices_.size() + mesh.vertices_.size() > std::size_t{0xFFFFFFFFu})
        throw Error("mesh builder: more than 2^32 vertices");
    vertices_.reserve(vertices_.size() + mesh.vertices_.size());
    for (const Float3& p : mesh.vertices_) vertices_.push_back(frame.point(p));
    indices_.reserve(indices_.size() + mesh.indices_.size());
    for (std::uint32_t i : mesh.indices_) indices_.push_back(base + i);
}

void MeshBuilder::begin_object() {
    if (!object_starts_.empty() && object_starts_.back() == triangle_count()) return;  // the last one is still empty
    object_starts_.push_back(triangle_count());
}

std::vector<std::uint32_t> MeshBuilder::object_of_triangle() const {
    std::vector<std::uint32_t> objects;
    if (object_starts_.empty()) return objects;
    objects.resize(triangle_count());
    // Triangles before the first start (if any) are object 0; the objects begun follow.
    const std::uint32_t first_id = object_starts_.front() == 0 ? 0u : 1u;
    std::size_t begun = 0;  // starts at or before t
    for (std::size_t t = 0; t < objects.size(); ++t) {
        while (begun < object_starts_.size() && object_starts_[begun] <= t) ++begun;
        objects[t] = begun == 0 ? 0u : first_id + static_cast<std::uint32_t>(begun - 1);
    }
    return objects;
}

Scene MeshBuilder::build() const {
    return Scene(std::span<const Float3>(vertices_), std::span<const std::uint32_t>(indices_));
}

}  // namespace beamtrace::scenes
