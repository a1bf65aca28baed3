#pragma once
// Small scenes built by hand for the oracle and comparison tests.
#include <cstdint>
#include <vector>

#include "beamtrace/scene.hpp"

namespace beamtrace::test {

// One triangle in the plane z = 1: (0,0,1), (2,0,1), (0,2,1).
inline Scene one_triangle() {
    const std::vector<Float3> v = {{0, 0, 1}, {2, 0, 1}, {0, 2, 1}};
    const std::vector<std::uint32_t> i = {0, 1, 2};
    return Scene(v, i);
}

// The unit square [0,1]^2 in the plane z = 0 as two triangles sharing the diagonal (0,0)-(1,1):
// triangle 0 = (0,0),(1,0),(1,1) below the diagonal, triangle 1 = (0,0),(1,1),(0,1) above it.
inline Scene two_triangles() {
    const std::vector<Float3> v = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const std::vector<std::uint32_t> i = {0, 1, 2, 0, 2, 3};
    return Scene(v, i);
}

// The cube [-1,1]^3, two triangles per face, 12 triangles. Face f (0..5) is made of triangles 2f
// and 2f+1; the faces are -x, +x, -y, +y, -z, +z in that order.
inline Scene cube() {
    std::vector<Float3> v;
    for (int i = 0; i < 8; ++i) v.push_back({(i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? 1.0f : -1.0f});
    // Corner index = x + 2y + 4z with bits 1 for +1.
    const std::vector<std::uint32_t> i = {
        0, 4, 6, 0, 6, 2,  // -x
        1, 3, 7, 1, 7, 5,  // +x
        0, 1, 5, 0, 5, 4,  // -y
        2, 6, 7, 2, 7, 3,  // +y
        0, 2, 3, 0, 3, 1,  // -z
        4, 5, 7, 4, 7, 6,  // +z
    };
    return Scene(v, i);
}

// Degenerate triangles around one good one: 0 collinear along x at z = 1, 1 repeated corner at
// z = 2, 2 the good triangle (0,0,0),(1,0,0),(0,1,0), 3 all corners equal at (0.25,0.25,3),
// 4 collinear along the diagonal at z = 4.
inline Scene with_degenerates() {
    const std::vector<Float3> v = {{0, 0, 1}, {1, 0, 1}, {2, 0, 1},         {0, 0, 2}, {1, 1, 2},       {0, 0, 0},
                                   {1, 0, 0}, {0, 1, 0}, {0.25f, 0.25f, 3}, {0, 0, 4}, {0.5f, 0.5f, 4}, {1, 1, 4}};
    const std::vector<std::uint32_t> i = {0, 1, 2, 3, 4, 4, 5, 6, 7, 8, 8, 8, 9, 10, 11};
    return Scene(v, i);
}

}  // namespace beamtrace::test
