#include "hand_tree.hpp"

#include <cmath>

#include "common/triangle_kernels.hpp"
#include "common/triangle_reference.hpp"

namespace beamtrace::mlrta::test {

HandTree::HandTree(Float3 lower, Float3 upper) {
    bounds_.lower = lower;
    bounds_.upper = upper;
}

std::uint32_t HandTree::triangle(Float3 a, Float3 b, Float3 c) {
    const auto base = std::uint32_t(vertices_.size());
    vertices_.insert(vertices_.end(), {a, b, c});
    indices_.insert(indices_.end(), {base, base + 1, base + 2});
    return base / 3;
}

std::uint32_t HandTree::inner(int axis, float split, const std::function<void()>& lower,
                              const std::function<void()>& upper) {
    const std::uint32_t index = next_node();
    nodes_.push_back(KdNode::inner(axis, split, 0));
    lower();
    nodes_[index] = KdNode::inner(axis, split, next_node());
    upper();
    return index;
}

std::uint32_t HandTree::leaf(std::vector<std::uint32_t> triangles) {
    const std::uint32_t index = next_node();
    nodes_.push_back(KdNode::leaf(std::uint32_t(ids_.size()), std::uint32_t(triangles.size())));
    ids_.insert(ids_.end(), triangles.begin(), triangles.end());
    return index;
}

KdTree HandTree::tree() const {
    auto impl = std::make_shared<KdTree::Impl>(Scene(vertices_, indices_));
    impl->bounds = bounds_;
    impl->nodes = nodes_;
    impl->triangle_ids = ids_;
    impl->gather_leaf_triangles();
    impl->kernels = &triangle_kernels();
    return detail::Access::make_tree(impl);
}

std::shared_ptr<const Mlrta::Impl> HandTree::mlrta(const MlrtaSettings& settings) const {
    return make_mlrta(tree(), settings);
}

std::shared_ptr<const Mlrta::Impl> make_mlrta(const KdTree& tree, const MlrtaSettings& settings) {
    return detail::Access::share(Mlrta(tree, settings));
}

namespace {

bool find_box(const KdTree::Impl& tree, std::uint32_t at, const Box& box, std::uint32_t target, Box& out) {
    if (at == target) {
        out = box;
        return true;
    }
    const KdNode& n = tree.nodes[at];
    if (n.is_leaf()) return false;
    Box lower = box, upper = box;
    lower.upper[n.axis()] = n.split;
    upper.lower[n.axis()] = n.split;
    return find_box(tree, at + 1, lower, target, out) || find_box(tree, n.upper_child(), upper, target, out);
}

}  // namespace

Box node_box(const KdTree::Impl& tree, std::uint32_t index) {
    Box out;
    EXPECT_TRUE(find_box(tree, 0, tree.bounds, index, out)) << "node " << index << " is not in the tree";
    return out;
}

EntryPoint entry_at(const Mlrta::Impl& m, std::uint32_t node) {
    EntryPoint ep;
    ep.node = node;
    ep.box = node_box(m.kd(), node);
    return ep;
}

bool segment_meets_box(const Ray& ray, const Box& box) {
    double t0 = ray.tnear, t1 = ray.tfar;
    for (int k = 0; k < 3; ++k) {
        const double o = ray.org[k], d = ray.dir[k], lo = box.lower[k], hi = box.upper[k];
        if (d == 0.0) {
            if (o < lo || o > hi) return false;
            continue;
        }
        double a = (lo - o) / d, b = (hi - o) / d;
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    return t0 <= t1;
}

double plane_coordinate(const Ray& ray, int k, double p, int j) {
    return double(ray.org[j]) + (p - double(ray.org[k])) * double(ray.dir[j]) / double(ray.dir[k]);
}

double plane_parameter(const Ray& ray, int k, double p, int main_axis) {
    const double t = (p - double(ray.org[k])) / double(ray.dir[k]);
    return (t - double(ray.tnear)) * std::fabs(double(ray.dir[main_axis]));
}

float uniform(Rng& rng, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }

std::vector<Ray> bundle(Rng& rng, int n, Float3 org, float spread_org, Float3 dir, float spread_dir) {
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        Ray r;
        for (int k = 0; k < 3; ++k) {
            r.org[k] = org[k] + uniform(rng, -spread_org, spread_org);
            r.dir[k] = dir[k] * (1.0f + uniform(rng, -spread_dir, spread_dir));
        }
        rays.push_back(r);
    }
    return rays;
}

Beam beam_of(const std::vector<Ray>& rays, const Box* scene) {
    Beam b;
    if (scene) b.set_scene_scale(*scene);
    for (const Ray& r : rays) b.add(r);
    return b;
}

Beam packet_beam_of(const std::vector<Ray>& rays, const Box* scene) {
    Packet16 p;
    p.active = 0;
    for (std::size_t i = 0; i < 16; ++i) {
        p.set_ray(int(i), i < rays.size() ? rays[i] : Ray{{NAN, NAN, NAN}, 0.0f, {-1, -1, -1}, kInfinity});
        if (i < rays.size()) p.active |= 1u << i;
    }
    Beam b;
    if (scene) b.set_scene_scale(*scene);
    b.add(p);
    return b;
}

Packet16 packet_of(const std::vector<Ray>& rays, std::uint32_t active) {
    Packet16 p;
    for (int i = 0; i < 16; ++i) p.set_ray(i, rays.at(std::size_t(i)));
    p.active = active;
    return p;
}

Scene random_soup(int n, unsigned seed, float size) {
    Rng rng(seed);
    std::vector<Float3> v;
    std::vector<std::uint32_t> idx;
    for (int i = 0; i < n; ++i) {
        const Float3 c{uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, 0, 1)};
        for (int j = 0; j < 3; ++j) {
            idx.push_back(std::uint32_t(v.size()));
            v.push_back(c + Float3{uniform(rng, -size, size), uniform(rng, -size, size), uniform(rng, -size, size)});
        }
    }
    return Scene(v, idx);
}

Scene box_room(int n, unsigned seed) {
    Rng rng(seed);
    std::vector<Float3> v;
    std::vector<std::uint32_t> idx;
    auto quad = [&](Float3 a, Float3 b, Float3 c, Float3 d) {
        const auto base = std::uint32_t(v.size());
        v.insert(v.end(), {a, b, c, d});
        idx.insert(idx.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    };
    auto box = [&](Float3 l, Float3 h) {
        const Float3 p[8] = {{l.x, l.y, l.z}, {h.x, l.y, l.z}, {h.x, h.y, l.z}, {l.x, h.y, l.z},
                             {l.x, l.y, h.z}, {h.x, l.y, h.z}, {h.x, h.y, h.z}, {l.x, h.y, h.z}};
        quad(p[0], p[3], p[2], p[1]);
        quad(p[4], p[5], p[6], p[7]);
        quad(p[0], p[1], p[5], p[4]);
        quad(p[2], p[3], p[7], p[6]);
        quad(p[1], p[2], p[6], p[5]);
        quad(p[0], p[4], p[7], p[3]);
    };
    box({0, 0, 0}, {8, 8, 4});  // the room
    std::uniform_int_distribution<int> cell(0, 7);
    for (int i = 0; i < n; ++i) {
        const float x = float(cell(rng)), y = float(cell(rng)), h = float(1 + cell(rng) % 3);
        box({x, y, 0}, {x + 1, y + 1, h});
    }
    return Scene(v, idx);
}

Ray Camera::ray(int px, int py) const {
    const float sx = float(px) + 0.5f - float(width) * 0.5f, sy = float(py) + 0.5f - float(height) * 0.5f;
    return Ray{eye, 0.0f, forward + right * sx + up * sy, kInfinity};
}

std::vector<Packet16> Camera::packets() const {
    const int columns = width / 4, rows = height / 4;
    std::vector<Packet16> out(std::size_t(columns) * std::size_t(rows));
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < columns; ++x) {
            Packet16& p = out[std::size_t(y) * std::size_t(columns) + std::size_t(x)];
            for (int i = 0; i < 16; ++i) p.set_ray(i, ray(x * 4 + i % 4, y * 4 + i / 4));
            p.active = 0xFFFFu;
        }
    return out;
}

namespace {

::testing::AssertionResult equal_hits(const KdTree& tree, const Ray& ray, const Hit& want, const Hit& got) {
    if (want.hit() != got.hit())
        return ::testing::AssertionFailure()
               << "expected hit " << want.hit() << " (t " << want.t << ", triangle " << want.triangle << "), got hit "
               << got.hit() << " (t " << got.t << ", triangle " << got.triangle << ")";
    if (!want.hit()) return ::testing::AssertionSuccess();
    if (want.t != got.t)
        return ::testing::AssertionFailure() << "expected t " << want.t << " (triangle " << want.triangle << "), got t "
                                             << got.t << " (triangle " << got.triangle << ")";
    if (want.triangle == got.triangle) {
        if (want.u != got.u || want.v != got.v) return ::testing::AssertionFailure() << "same triangle, other u, v";
        return ::testing::AssertionSuccess();
    }
    TriangleHit h{};
    if (got.triangle < tree.scene().triangle_count() &&
        intersect_triangle(make_watertight_ray(ray), tree.scene().triangle(got.triangle), h) && h.t == got.t)
        return ::testing::AssertionSuccess();  // a tie: another triangle at exactly the same t
    return ::testing::AssertionFailure() << "triangle " << got.triangle << " is not met at t " << got.t;
}

}  // namespace

::testing::AssertionResult same_hit(const KdTree& tree, const Ray& ray, const Hit& got) {
    const ::testing::AssertionResult kd = equal_hits(tree, ray, tree.intersect(ray), got);
    if (kd) return kd;
    const ::testing::AssertionResult exact = equal_hits(tree, ray, intersect_brute_force(tree.scene(), ray), got);
    if (exact) return exact;
    return ::testing::AssertionFailure() << "kd-tree: " << kd.message() << "; brute force: " << exact.message();
}

::testing::AssertionResult same_occlusion(const KdTree& tree, const Ray& ray, bool got) {
    const bool kd = tree.occluded(ray);
    if (got == kd || got == occluded_brute_force(tree.scene(), ray)) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "occluded " << got << ", the kd-tree and brute force say " << kd;
}

}  // namespace beamtrace::mlrta::test
