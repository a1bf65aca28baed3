#pragma once
// The procedural scenes behind load_scene's "random:", "tetra:", "sphereflake:" and "room" specs,
// callable directly. Each validates its parameter (throws beamtrace::Error with the range) and is
// deterministic: the same arguments give bit-identical scenes on every run and machine.
#include <cstddef>
#include <cstdint>

#include "scenes/scene_source.hpp"

namespace beamtrace::scenes {

inline constexpr std::size_t kMaxRandomTriangles = 10'000'000;
inline constexpr std::uint32_t kDefaultRandomSeed = 2007;  // the year of the VLF-RT paper
inline constexpr int kMaxTetraLevel = 10;
inline constexpr int kMaxSphereflakeLevel = 5;
inline constexpr std::uint32_t kDefaultRoomSeed = 1;

// `count` small random triangles in the unit cube (VLF-RT section 6.1), 1..kMaxRandomTriangles.
SceneSource random_triangles(std::size_t count, std::uint32_t seed = kDefaultRandomSeed);
// Corners of a random triangle lie within +-h of its centre on each axis; h = 0.2 / cbrt(count).
float random_triangle_half_size(std::size_t count);
// Haines' Sierpinski tetrahedron: 4^level closed tetrahedra, 4^(level+1) triangles, level 0..10.
SceneSource sierpinski_tetra(int level);
// Haines' sphereflake: a sphere with 9 children of a third its radius, `level` generations deep
// (level 0 is one sphere), each a closed tessellated sphere. Level 0..5.
SceneSource sphereflake(int level);
// A furnished classroom of about a million triangles; the seed moves furniture and desk objects.
SceneSource room(std::uint32_t seed = kDefaultRoomSeed);
// The same classroom (same seed, same places) with its desk objects tessellated kRoomLiteCoarseness
// times coarser along each direction: about 19,000 triangles, for engines without a geometry
// hierarchy (brute, crsh, rah).
inline constexpr int kRoomLiteCoarseness = 8;
SceneSource room_lite(std::uint32_t seed = kDefaultRoomSeed);

}  // namespace beamtrace::scenes
