#pragma once
// Small scenes and ray sets built in the test itself (no file, no other module), shaped to reach
// the kd-tree's special cases: triangle soup, axis-aligned boxes (planar triangles on split planes),
// a single plane, coincident triangles.
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/kdtree.hpp"
#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"

namespace beamtrace::test {

struct Soup {
    std::vector<Float3> vertices;
    std::vector<std::uint32_t> indices;

    void add(Float3 a, Float3 b, Float3 c);
    void add_quad(Float3 a, Float3 b, Float3 c, Float3 d);
    void add_box(Float3 lo, Float3 hi);
    Scene scene() const { return Scene(vertices, indices); }
};

Scene random_soup(int n, unsigned seed, float size = 0.1f);
Scene stacked_boxes(int n, unsigned seed);  // axis-aligned boxes on a floor, inside a closed room
Scene single_plane(int n);                  // an n x n grid of quads in z = 0.5
std::vector<Ray> random_rays(const Box& box, int n, unsigned seed);  // origins in and around the box
// Rays whose direction has exact zero (and -0) components, with origins snapped to coordinates
// that appear in the scene (so they run inside split planes).
std::vector<Ray> axis_rays(const Scene& scene, int n, unsigned seed);

// The kd-tree builders the tests run: the exact sweep everywhere ("exact"), binned levels above 64
// references with 16 bins ("binned"), and binned in every cell of more than one reference with 2
// bins, the coarsest setting ("binned_coarsest").
struct BuildCase {
    std::string name;
    KdBuildRules rules;
};
std::vector<BuildCase> build_cases();
inline void PrintTo(const BuildCase& c, std::ostream* os) { *os << c.name; }

}  // namespace beamtrace::test
