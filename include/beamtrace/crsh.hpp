#pragma once
// CRSH (Reis, Costa, Pereira: "Coherent Ray-Space Hierarchy via Ray Hashing and Sorting", GRAPP 2017)
// and, with two switches off, RAH (Roger, Assarsson, Holzschuch: "Whitted Ray-Tracing for Dynamic
// Scenes using a Ray-Space Hierarchy on the GPU", EGSR 2007).
//
// A hierarchy over the rays of one call, not over the scene: each ray gets a key (hash) from the
// point it is bounded from and its direction, the (key, index) pairs are radix-sorted, `fanout`
// consecutive sorted rays make a level-1 node (a sphere bounding where their segments start and a
// cone bounding their directions, grown by Szecsi's formulas), `fanout` consecutive nodes make a
// node of the next level, up to `levels`. Each top node is tested against the objects' bounding
// spheres, the triangles of the objects it meets against the node's sphere-cone by their own
// bounding spheres, the survivors against each child, level by level, and finally every ray of a
// level-1 node against the triangles that survived it, with the library's watertight test (closest
// hit: the smallest t, at equal t the smaller triangle id, as brute force; occlusion: any hit). The
// answers are exact: the hierarchy only culls what no ray of a node can hit.
//
// There is no geometry hierarchy: a call costs at least (top nodes) x (objects) sphere tests and,
// without object spheres, (top nodes) x (triangles). See predicted_top_level_tests() and
// docs/crsh.md for the budget the tools apply.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"

namespace beamtrace {

namespace detail {
struct Access;  // the library's own access to the implementation (never part of the API)
}

// Which point of a ray its key and its node's sphere take (the paper's hash kinds):
//   origin:    where the segment starts (org + tnear * dir), direction dir (reflection, refraction,
//              AO, camera rays);
//   end_point: where the segment ends (org + tfar * dir), direction -dir: shadow rays "moved to the
//              light" (the light index of the paper's key becomes the quantised end point). Rays with
//              an infinite tfar are keyed and bounded from their origin. Only the bounds use the
//              reversed form; every ray is still tested as given, so the answers do not change.
enum class CrshKey { origin, end_point };

struct CrshSettings {
    int fanout = 8;    // rays per level-1 node and children per upper node (the paper's "subdivision" 8)
    int levels = 2;    // levels of nodes above the rays, 1..4 (the paper's depth 2)
    bool sort = true;  // hash and radix-sort the rays; false: nodes of consecutive input rays (RAH)
    // Test each top node against the objects' bounding spheres before their triangles (CRSH); false:
    // every triangle against every top node (RAH).
    bool object_spheres = true;
    CrshKey key = CrshKey::origin;
    // Not in the paper (the notes' proposal): also cull by the segments' lengths. A node whose rays
    // run at most L from their starts cannot reach a sphere farther than (node radius + L + sphere
    // radius) from its centre, whatever its cone; this culls for short rays (AO) even with cones of
    // 90 degrees and more, which accept everything otherwise. Off: the paper's half-infinite cones.
    bool segment_bound = false;
    // Bits per axis of the quantised position in the key (0..10): the position in the scene's box, in
    // Morton order, above 31 bits of direction (cube face, then Morton order of the face coordinates).
    int key_position_bits = 10;
    // Object of each triangle (any ids; triangles with the same id form one object), read by the
    // constructor only. Empty: the whole scene is one object. Otherwise its size must be the scene's
    // triangle count.
    std::span<const std::uint32_t> object_of_triangle;

    // Throws beamtrace::Error naming the bad setting.
    void validate() const;
};

struct CrshStats {
    std::size_t triangles = 0;             // in the scene
    std::size_t degenerate_triangles = 0;  // zero-area triangles, never tested
    std::size_t objects = 0;               // objects with at least one non-degenerate triangle
    std::size_t largest_object = 0;        // non-degenerate triangles of the largest object
    std::size_t memory_bytes = 0;          // triangle copies, triangle and object spheres
    double build_seconds = 0.0;            // bounding spheres of the triangles and the objects
};

class Crsh {
public:
    // Copies the scene's non-degenerate triangles in object order and computes their bounding spheres
    // (smallest sphere of the three corners) and the objects' (box centre, farthest corner), radii
    // rounded up. Throws beamtrace::Error for bad settings or a partition of the wrong size.
    explicit Crsh(const Scene& scene, const CrshSettings& settings = {});

    // The same structure, keying and bounding rays from another point (shadow rays: end_point).
    Crsh with_key(CrshKey key) const;

    // The query contract (query.hpp). Each call builds the hierarchy of its rays (keys, sort, nodes)
    // and traverses it; a single ray is a call of one. Span calls with QueryOptions::threads > 1 run
    // the keys, the nodes and the traversal (by top node) on that many threads; the sort is serial.
    // Counters: crsh.* (and triangle_tests) of the counting variant of the same code.
    Hit intersect(const Ray& ray) const;
    bool occluded(const Ray& ray) const;
    void intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options = {}) const;
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded, const QueryOptions& options = {}) const;
    void intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                   const QueryOptions& options = {}) const;
    void occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                  const QueryOptions& options = {}) const;

    // Sphere tests the top level of a call over `rays` rays (all describing segments) makes before
    // the levels below: (top nodes) x (objects + triangles of the largest object) with object spheres
    // (each top node meets at least one object; a scene of one object costs every triangle), else
    // (top nodes) x (non-degenerate triangles).
    std::uint64_t predicted_top_level_tests(std::size_t rays) const;

    const Scene& scene() const;
    const CrshSettings& settings() const { return settings_; }  // object_of_triangle is left empty
    const CrshStats& stats() const;

    struct Impl;  // opaque

private:
    friend struct detail::Access;
    Crsh(std::shared_ptr<const Impl> impl, const CrshSettings& settings)
        : impl_(std::move(impl)), settings_(settings) {}
    std::shared_ptr<const Impl> impl_;
    CrshSettings settings_;
};

}  // namespace beamtrace
