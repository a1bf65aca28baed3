// Desk objects: lathes, tori and tubes in a local unit space (standing on y = 0, inside the unit
// cylinder about +y), scaled and turned into place by one frame.
#include "scenes/desk_objects.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace beamtrace::scenes {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

Frame moved(Float3 offset) { return Frame{offset, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}; }

// A tessellation count divided by the coarseness, never below `least`.
struct Detail {
    int coarseness = 1;
    int operator()(int count, int least = 3) const { return std::max(least, count / coarseness); }
    std::size_t points(std::size_t count, std::size_t least) const {
        return std::max(least, count / static_cast<std::size_t>(coarseness));
    }
};

// `count` points along the polyline through `keys`, keeping every key point (so sharp rims stay
// sharp) and spreading the others over the segments in proportion to their lengths.
std::vector<ProfilePoint> polyline_profile(const std::vector<ProfilePoint>& keys, std::size_t count) {
    const std::size_t segments = keys.size() - 1, extra = count - keys.size();
    std::vector<float> len(segments);
    float total = 0.0f;
    for (std::size_t i = 0; i < segments; ++i)
        total += len[i] = std::hypot(keys[i + 1].r - keys[i].r, keys[i + 1].y - keys[i].y);
    std::vector<std::size_t> inner(segments);
    std::vector<std::pair<float, std::size_t>> remainder(segments);
    std::size_t given = 0;
    for (std::size_t i = 0; i < segments; ++i) {
        const float share = static_cast<float>(extra) * len[i] / total;
        inner[i] = static_cast<std::size_t>(share);
        given += inner[i];
        remainder[i] = {share - static_cast<float>(inner[i]), i};
    }
    std::sort(remainder.begin(), remainder.end(),
              [](auto a, auto b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
    for (std::size_t k = 0; given < extra; ++k, ++given) ++inner[remainder[k % segments].second];
    std::vector<ProfilePoint> out;
    out.reserve(count);
    for (std::size_t i = 0; i < segments; ++i) {
        out.push_back(keys[i]);
        for (std::size_t j = 1; j <= inner[i]; ++j) {
            const float f = static_cast<float>(j) / static_cast<float>(inner[i] + 1);
            out.push_back({keys[i].r + f * (keys[i + 1].r - keys[i].r), keys[i].y + f * (keys[i + 1].y - keys[i].y)});
        }
    }
    out.push_back(keys.back());
    return out;
}

// A profile of `count` points from the curve (r(t), y(t)), t in [0, 1], poles forced onto the axis.
template <class Curve>
std::vector<ProfilePoint> curve_profile(std::size_t count, Curve curve) {
    std::vector<ProfilePoint> p(count);
    for (std::size_t i = 0; i < count; ++i) p[i] = curve(static_cast<float>(i) / static_cast<float>(count - 1));
    p.front().r = 0.0f;
    p.back().r = 0.0f;
    return p;
}

void ball(MeshBuilder& m, const Frame& f, Detail k) { m.add_uv_sphere(f * moved({0, 1, 0}), k(120), k(63, 2)); }

void ring(MeshBuilder& m, const Frame& f, Detail k) { m.add_torus(f * moved({0, 0.3f, 0}), 0.7f, 0.3f, k(150), k(50)); }

void teapot(MeshBuilder& m, const Frame& outer, Detail k) {
    const Frame f = outer.scaled(0.9f, 0.9f, 0.9f);
    // Body: a squashed ball with a slightly wider shoulder.
    m.add_lathe(f,
                curve_profile(k.points(60, 3),
                              [](float t) {
                                  const float a = kPi * t;
                                  return ProfilePoint{0.72f * std::sin(a) * (1.0f + 0.06f * std::sin(2.0f * a)),
                                                      0.55f - 0.52f * std::cos(a)};
                              }),
                k(96));
    m.add_uv_sphere(f * moved({0, 1.1f, 0}).scaled(0.12f, 0.12f, 0.12f), k(32), k(10, 2));  // lid knob
    // Spout: a narrowing cone rising from the side of the body.
    const std::vector<ProfilePoint> spout =
        polyline_profile({{0, 0}, {0.16f, 0}, {0.07f, 0.62f}, {0, 0.62f}}, k.points(22, 4));
    m.add_lathe(f * Frame::along({0.5f, 0.4f, 0}, {1.0f, 1.1f, 0}), spout, k(32));
    // Handle: an upright ring half sunk into the back of the body.
    m.add_torus(f * Frame::along({-0.74f, 0.6f, 0}, {0, 0, 1}), 0.27f, 0.06f, k(64), k(16));
}

void vase(MeshBuilder& m, const Frame& f, Detail k) {
    m.add_lathe(f,
                curve_profile(k.points(60, 3),
                              [](float t) {
                                  const float belly = std::sin(kPi * t);
                                  return ProfilePoint{0.3f + 0.55f * belly * belly * (1.0f - 0.4f * t) +
                                                          0.04f * std::sin(10.0f * kPi * t),
                                                      2.2f * t};
                              }),
                k(128));
}

void cup(MeshBuilder& m, const Frame& outer, Detail k) {
    const Frame f = outer.scaled(0.82f, 0.82f, 0.82f);
    // Outside down to the foot, up the outer wall, over the rim, down the inner wall, the inside floor.
    const std::vector<ProfilePoint> keys{{0, 0},        {0.62f, 0},     {0.7f, 0.08f}, {0.75f, 1.2f},
                                         {0.68f, 1.2f}, {0.63f, 0.14f}, {0, 0.14f}};
    m.add_lathe(f, polyline_profile(keys, k.points(60, keys.size())), k(112));
    m.add_torus(f * Frame::along({0.86f, 0.65f, 0}, {0, 0, 1}), 0.3f, 0.06f, k(64), k(16));  // handle
}

void trefoil_knot(MeshBuilder& m, const Frame& f, Detail k) {
    // The trefoil (sin t + 2 sin 2t, cos t - 2 cos 2t, -sin 3t) lying on the desk, shrunk into the
    // unit cylinder: its loops stay within radius 3, its height within +-1, plus the tube.
    const int samples = k(300);
    constexpr float kTube = 0.3f, kShrink = 1.0f / 3.3f;
    std::vector<Float3> curve(static_cast<std::size_t>(samples));
    for (std::size_t i = 0; i < curve.size(); ++i) {
        const float t = 2.0f * kPi * static_cast<float>(i) / static_cast<float>(samples);
        const float x = std::sin(t) + 2.0f * std::sin(2.0f * t), y = std::cos(t) - 2.0f * std::cos(2.0f * t);
        const float z = -std::sin(3.0f * t);
        curve[i] = Float3{x, z + 1.0f + kTube, y} * kShrink;
    }
    m.add_tube(f, curve, kTube * kShrink, k(25));
}

void bottle(MeshBuilder& m, const Frame& f, Detail k) {
    const std::vector<ProfilePoint> keys{{0, 0},        {0.45f, 0},     {0.5f, 0.05f},  {0.5f, 1.1f}, {0.2f, 1.5f},
                                         {0.15f, 1.9f}, {0.18f, 1.95f}, {0.18f, 2.05f}, {0, 2.05f}};
    m.add_lathe(f, polyline_profile(keys, k.points(60, keys.size())), k(128));
}

void ring_tower(MeshBuilder& m, const Frame& f, Detail k) {
    const std::vector<ProfilePoint> pole{{0, 0}, {0.12f, 0}, {0.12f, 1.5f}, {0, 1.5f}};
    m.add_lathe(f, pole, k(16));
    m.add_torus(f * moved({0, 0.25f, 0}), 0.7f, 0.25f, k(100), k(25));
    m.add_torus(f * moved({0, 0.7f, 0}), 0.5f, 0.2f, k(100), k(25));
    m.add_torus(f * moved({0, 1.05f, 0}), 0.32f, 0.15f, k(100), k(25));
}

}  // namespace

const char* desk_object_name(DeskObject kind) {
    switch (kind) {
        case DeskObject::ball:
            return "ball";
        case DeskObject::ring:
            return "ring";
        case DeskObject::teapot:
            return "teapot";
        case DeskObject::vase:
            return "vase";
        case DeskObject::cup:
            return "cup";
        case DeskObject::trefoil_knot:
            return "trefoil knot";
        case DeskObject::bottle:
            return "bottle";
        case DeskObject::ring_tower:
            return "ring tower";
    }
    return "?";
}

std::size_t add_desk_object(MeshBuilder& mesh, DeskObject kind, Float3 base, float footprint, float yaw_radians,
                            int coarseness) {
    const std::size_t before = mesh.triangle_count();
    const Frame f = Frame::upright(base, yaw_radians, footprint);
    const Detail k{std::max(1, coarseness)};
    switch (kind) {
        case DeskObject::ball:
            ball(mesh, f, k);
            break;
        case DeskObject::ring:
            ring(mesh, f, k);
            break;
        case DeskObject::teapot:
            teapot(mesh, f, k);
            break;
        case DeskObject::vase:
            vase(mesh, f, k);
            break;
        case DeskObject::cup:
            cup(mesh, f, k);
            break;
        case DeskObject::trefoil_knot:
            trefoil_knot(mesh, f, k);
            break;
        case DeskObject::bottle:
            bottle(mesh, f, k);
            break;
        case DeskObject::ring_tower:
            ring_tower(mesh, f, k);
            break;
    }
    return mesh.triangle_count() - before;
}

std::size_t desk_object_triangles(DeskObject kind, int coarseness) {
    MeshBuilder scratch;
    return add_desk_object(scratch, kind, {0, 0, 0}, 1.0f, 0.0f, coarseness);
}

}  // namespace beamtrace::scenes
