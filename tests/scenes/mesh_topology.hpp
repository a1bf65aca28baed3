#pragma once
// Test helper: is an indexed triangle mesh a closed, consistently oriented 2-manifold?
#include <cstddef>
#include <cstdint>
#include <span>
#include <unordered_map>

#include "beamtrace/vec.hpp"

namespace beamtrace::scenes::testing {

struct Topology {
    std::size_t edges = 0;                       // undirected edges
    std::size_t edges_not_shared_by_two = 0;     // used by 1 or 3+ triangles: holes or fins
    std::size_t directed_edges_repeated = 0;     // the same directed edge twice: inconsistent orientation
    std::size_t degenerate_index_triangles = 0;  // a triangle naming one vertex twice
    double signed_volume = 0.0;                  // positive for closed meshes facing outward

    bool closed() const {
        return edges_not_shared_by_two == 0 && directed_edges_repeated == 0 && degenerate_index_triangles == 0;
    }
};

inline Topology topology(std::span<const Float3> vertices, std::span<const std::uint32_t> indices) {
    Topology t;
    std::unordered_map<std::uint64_t, int> directed;
    directed.reserve(indices.size());
    for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
        const std::uint32_t c[3] = {indices[i], indices[i + 1], indices[i + 2]};
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) ++t.degenerate_index_triangles;
        for (int k = 0; k < 3; ++k) ++directed[(std::uint64_t{c[k]} << 32) | c[(k + 1) % 3]];
        const Float3 a = vertices[c[0]], b = vertices[c[1]], d = vertices[c[2]];
        t.signed_volume += (double(a.x) * (double(b.y) * d.z - double(b.z) * d.y) -
                            double(a.y) * (double(b.x) * d.z - double(b.z) * d.x) +
                            double(a.z) * (double(b.x) * d.y - double(b.y) * d.x)) /
                           6.0;
    }
    for (const auto& [key, count] : directed) {
        const std::uint32_t from = static_cast<std::uint32_t>(key >> 32), to = static_cast<std::uint32_t>(key);
        if (count > 1) ++t.directed_edges_repeated;
        const auto reverse = directed.find((std::uint64_t{to} << 32) | from);
        const int back = reverse == directed.end() ? 0 : reverse->second;
        if (from < to || back == 0) {
            ++t.edges;
            if (count + back != 2) ++t.edges_not_shared_by_two;
        }
    }
    return t;
}

}  // namespace beamtrace::scenes::testing
