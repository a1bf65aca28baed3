#include "test_scenes.hpp"

namespace beamtrace::test {

void Soup::add(Float3 a, Float3 b, Float3 c) {
    const auto base = std::uint32_t(vertices.size());
    vertices.insert(vertices.end(), {a, b, c});
    indices.insert(indices.end(), {base, base + 1, base + 2});
}

void Soup::add_quad(Float3 a, Float3 b, Float3 c, Float3 d) {
    add(a, b, c);
    add(a, c, d);
}

void Soup::add_box(Float3 l, Float3 h) {
    const Float3 p[8] = {{l.x, l.y, l.z}, {h.x, l.y, l.z}, {h.x, h.y, l.z}, {l.x, h.y, l.z},
                         {l.x, l.y, h.z}, {h.x, l.y, h.z}, {h.x, h.y, h.z}, {l.x, h.y, h.z}};
    add_quad(p[0], p[3], p[2], p[1]);
    add_quad(p[4], p[5], p[6], p[7]);
    add_quad(p[0], p[1], p[5], p[4]);
    add_quad(p[2], p[3], p[7], p[6]);
    add_quad(p[1], p[2], p[6], p[5]);
    add_quad(p[0], p[4], p[7], p[3]);
}

Scene random_soup(int n, unsigned seed, float size) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), d(-size, size);
    Soup s;
    for (int i = 0; i < n; ++i) {
        const Float3 c{u(rng), u(rng), u(rng)};
        s.add(c + Float3{d(rng), d(rng), d(rng)}, c + Float3{d(rng), d(rng), d(rng)},
              c + Float3{d(rng), d(rng), d(rng)});
    }
    return s.scene();
}

Scene stacked_boxes(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> cell(0, 15);
    Soup s;
    s.add_box({-1, -1, -1}, {17, 17, 9});  // the room (seen from inside)
    for (int i = 0; i < n; ++i) {
        const float x = float(cell(rng)), y = float(cell(rng)), h = float(1 + cell(rng) % 4);
        s.add_box({x, y, 0}, {x + 1, y + 1, h});  // boxes share faces and edges on the integer grid
    }
    return s.scene();
}

Scene single_plane(int n) {
    Soup s;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const float x0 = float(i) / float(n), x1 = float(i + 1) / float(n);
            const float y0 = float(j) / float(n), y1 = float(j + 1) / float(n);
            s.add_quad({x0, y0, 0.5f}, {x1, y0, 0.5f}, {x1, y1, 0.5f}, {x0, y1, 0.5f});
        }
    return s.scene();
}

std::vector<Ray> random_rays(const Box& box, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-0.2f, 1.2f), d(-1.0f, 1.0f);
    const Float3 e = box.extent();
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        Ray r;
        r.org = box.lower + Float3{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z};
        do r.dir = Float3{d(rng), d(rng), d(rng)};
        while (dot(r.dir, r.dir) < 1e-4f);
        rays.push_back(r);
    }
    return rays;
}

std::vector<Ray> axis_rays(const Scene& scene, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::vector<Ray> rays;
    const auto verts = scene.vertices();
    std::uniform_int_distribution<std::size_t> pickv(0, verts.size() - 1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const Box& b = scene.bounds();
    for (int i = 0; i < n; ++i) {
        Ray r;
        for (int k = 0; k < 3; ++k)
            r.org[k] = (rng() % 2) ? verts[pickv(rng)][k] : b.lower[k] + u(rng) * (b.upper[k] - b.lower[k]);
        const int axis = int(rng() % 3);
        const float zero = (rng() % 2) ? 0.0f : -0.0f;
        r.dir = Float3{zero, zero, zero};
        r.dir[axis] = (rng() % 2) ? 1.0f : -1.0f;
        if (rng() % 3 == 0) r.dir[(axis + 1) % 3] = u(rng) - 0.5f;  // only one zero component
        rays.push_back(r);
    }
    return rays;
}

std::vector<BuildCase> build_cases() {
    KdBuildRules binned, coarsest;
    binned.binned_above = 64;
    binned.bins = 16;
    coarsest.binned_above = 1;
    coarsest.bins = 2;
    return {{"exact", KdBuildRules{}}, {"binned", binned}, {"binned_coarsest", coarsest}};
}

}  // namespace beamtrace::test
