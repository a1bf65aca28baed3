#pragma once
// Shared helpers of the MLRTA tests: kd-trees assembled node by node (to reach the exact cases of the
// paper's figures), exact double-precision ray geometry to judge culling decisions, random scenes,
// coherent ray bundles and pinhole-camera packet grids, and hit comparison against the kd-tree.
#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/kdtree.hpp"
#include "beamtrace/mlrta.hpp"
#include "kdtree/kd_node.hpp"
#include "mlrta/beam.hpp"
#include "mlrta/entry_point.hpp"
#include "common/access.hpp"
#include "mlrta/mlrta_impl.hpp"

namespace beamtrace::mlrta::test {

// A scene and its kd-tree written node by node in depth-first order (lower child = next node):
//   HandTree h({0, 0, 0}, {1, 1, 1});
//   h.inner(0, 0.5f, [&] { h.leaf({a}); }, [&] { h.leaf({}); });
class HandTree {
public:
    HandTree(Float3 lower, Float3 upper);

    std::uint32_t triangle(Float3 a, Float3 b, Float3 c);  // returns the triangle's id
    std::uint32_t inner(int axis, float split, const std::function<void()>& lower, const std::function<void()>& upper);
    std::uint32_t leaf(std::vector<std::uint32_t> triangles);
    std::uint32_t next_node() const { return std::uint32_t(nodes_.size()); }

    // The tree (valid once every node is written) and MLRTA's state over it, tables included.
    KdTree tree() const;
    std::shared_ptr<const Mlrta::Impl> mlrta(const MlrtaSettings& settings = {}) const;

private:
    Box bounds_;
    std::vector<Float3> vertices_;
    std::vector<std::uint32_t> indices_;
    std::vector<KdNode> nodes_;
    std::vector<std::uint32_t> ids_;
};

// MLRTA's state over a tree built by KdTree::build (what the public Mlrta constructor does).
std::shared_ptr<const Mlrta::Impl> make_mlrta(const KdTree& tree, const MlrtaSettings& settings = {});

// The box of node `index` (the root's box split down the path to it).
Box node_box(const KdTree::Impl& tree, std::uint32_t index);
EntryPoint entry_at(const Mlrta::Impl& m, std::uint32_t node);

// Exact (double precision) geometry of one ray.
bool segment_meets_box(const Ray& ray, const Box& box);                  // closed box, t in [tnear, tfar]
double plane_coordinate(const Ray& ray, int k, double p, int j);         // coordinate j of the line at x_k = p
double plane_parameter(const Ray& ray, int k, double p, int main_axis);  // t' of the beam at x_k = p

// Random helpers.
using Rng = std::mt19937;
float uniform(Rng& rng, float lo, float hi);
// A coherent bundle: origins in a box of half-size `spread_org` around `org`, directions around
// `dir` (every component kept on the sign of dir's) with relative jitter `spread_dir`.
std::vector<Ray> bundle(Rng& rng, int n, Float3 org, float spread_org, Float3 dir, float spread_dir);
Beam beam_of(const std::vector<Ray>& rays, const Box* scene = nullptr);
// The same rays (at most 16) as the active lanes of a packet, through Beam::add(Packet16).
Beam packet_beam_of(const std::vector<Ray>& rays, const Box* scene = nullptr);
Packet16 packet_of(const std::vector<Ray>& rays, std::uint32_t active = 0xFFFFu);  // rays.size() == 16

// A soup of n random triangles of size about `size` in [0,1]^3 and a closed room of axis-aligned boxes
// (flat, completely covered leaves appear in its tree).
Scene random_soup(int n, unsigned seed, float size = 0.08f);
Scene box_room(int n, unsigned seed);

// A pinhole camera: pixel (px, py) of a width x height image has direction
// forward + right * (px + 0.5 - width / 2) + up * (py + 0.5 - height / 2). Packets of 4x4 pixels.
struct Camera {
    Float3 eye, forward, right, up;
    int width, height;  // multiples of 4
    Ray ray(int px, int py) const;
    std::vector<Packet16> packets() const;  // row-major over packets: (width / 4) x (height / 4)
};

// `got` must be the closest hit the kd-tree finds for `ray`: the same t; the same triangle, or at a tie
// another triangle met at exactly that t. Where the kd-tree itself misses the brute-force closest hit
// (MlrtaReference.KdTreeEqualsBruteForceAtABoxEdge), the brute-force hit is accepted as well.
::testing::AssertionResult same_hit(const KdTree& tree, const Ray& ray, const Hit& got);
// `got` is the kd-tree's occlusion answer for `ray`, or else the brute-force one.
::testing::AssertionResult same_occlusion(const KdTree& tree, const Ray& ray, bool got);

}  // namespace beamtrace::mlrta::test
