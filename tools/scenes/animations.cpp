// The procedural animations (animations.hpp): keyframe arrays made from a static scene.
#include "scenes/animations.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_set>

#include "beamtrace/error.hpp"
#include "scenes/deterministic_random.hpp"
#include "scenes/mesh_builder.hpp"

namespace beamtrace::scenes {

namespace {

constexpr std::size_t kSmallObjectMinTriangles = 100;
constexpr double kSmallObjectMaxFraction = 0.05;
constexpr std::size_t kSpinObjects = 8;
constexpr int kSpinKeyframes = 13;
constexpr int kPartyKeyframes = 9;
constexpr int kMaxPartySpheres = 256;
constexpr int kPartySphereSubdivisions = 3;  // 1,280 triangles

std::vector<float> uniform_times(int keyframes) {
    std::vector<float> times(static_cast<std::size_t>(keyframes));
    for (int k = 0; k < keyframes; ++k) times[std::size_t(k)] = float(k) / float(keyframes - 1);
    return times;
}

// The vertices used by the triangles of one object.
std::vector<std::uint32_t> object_vertices(const SceneSource& source, std::uint32_t object) {
    const auto indices = source.scene.indices();
    std::unordered_set<std::uint32_t> seen;
    std::vector<std::uint32_t> vertices;
    for (std::size_t t = 0; t < source.object_of_triangle.size(); ++t) {
        if (source.object_of_triangle[t] != object) continue;
        for (int c = 0; c < 3; ++c)
            if (seen.insert(indices[3 * t + std::size_t(c)]).second) vertices.push_back(indices[3 * t + std::size_t(c)]);
    }
    std::sort(vertices.begin(), vertices.end());
    return vertices;
}

Box vertex_box(std::span<const Float3> vertices, const std::vector<std::uint32_t>& ids) {
    Box box;
    for (std::uint32_t v : ids) box.extend(vertices[v]);
    return box;
}

// The unit vector of the coordinate axis nearest the camera's up (y for the default up).
int up_axis(const Camera& camera) {
    const Float3 u = camera.up;
    const float a[3] = {std::fabs(u.x), std::fabs(u.y), std::fabs(u.z)};
    return a[1] >= a[0] && a[1] >= a[2] ? 1 : (a[2] >= a[0] ? 2 : 0);
}

float& coordinate(Float3& p, int axis) { return axis == 0 ? p.x : (axis == 1 ? p.y : p.z); }

// p turned by `angle` about the axis `axis` through `centre` (in double, rounded once).
Float3 turned(Float3 p, Float3 centre, int axis, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    const double d[3] = {double(p.x) - centre.x, double(p.y) - centre.y, double(p.z) - centre.z};
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;  // the plane turned: (a, b) -> (c a - s b, s a + c b)
    double r[3] = {d[0], d[1], d[2]};
    r[a] = c * d[a] - s * d[b];
    r[b] = s * d[a] + c * d[b];
    return {float(centre.x + r[0]), float(centre.y + r[1]), float(centre.z + r[2])};
}

std::vector<Float3> repeated(std::span<const Float3> vertices, int keyframes) {
    std::vector<Float3> frames;
    frames.reserve(vertices.size() * std::size_t(keyframes));
    for (int k = 0; k < keyframes; ++k) frames.insert(frames.end(), vertices.begin(), vertices.end());
    return frames;
}

AnimationSource finish(std::string name, const SceneSource& base, std::string description, std::vector<float> times,
                       const std::vector<Float3>& keyframes, std::size_t vertex_count,
                       std::span<const std::uint32_t> indices, Camera start, Camera end) {
    return AnimationSource{std::move(name), base.name, std::move(description),
                           AnimatedScene(times, keyframes, vertex_count, indices), start, end};
}

AnimationSource make_spin(const SceneSource& base) {
    const auto objects = small_objects(base, base.camera.at);
    if (objects.empty())
        throw Error("animation spin: scene " + base.name +
                    " has no small objects (parts of 100 triangles or more, at most 5% of the scene) to turn");
    const std::size_t turning = std::min(objects.size(), kSpinObjects);
    const auto vertices = base.scene.vertices();
    std::vector<Float3> frames = repeated(vertices, kSpinKeyframes);
    const int axis = up_axis(base.camera);
    std::size_t moved_triangles = 0;
    for (std::size_t o = 0; o < turning; ++o) {
        const auto ids = object_vertices(base, objects[o]);
        const Float3 centre = vertex_box(vertices, ids).center();
        for (int k = 1; k < kSpinKeyframes; ++k) {
            const double angle = 2.0 * std::numbers::pi * double(k) / double(kSpinKeyframes - 1);
            Float3* frame = frames.data() + std::size_t(k) * vertices.size();
            for (std::uint32_t v : ids) frame[v] = turned(vertices[v], centre, axis, angle);
        }
        moved_triangles += std::size_t(std::count(base.object_of_triangle.begin(), base.object_of_triangle.end(), objects[o]));
    }
    return finish("spin", base,
                  std::to_string(turning) + " objects of " + base.name + " (" + std::to_string(moved_triangles) +
                      " triangles) each turn once about the vertical",
                  uniform_times(kSpinKeyframes), frames, vertices.size(), base.scene.indices(), base.camera, base.camera);
}

AnimationSource make_comet(const SceneSource& base) {
    const auto objects = small_objects(base, base.camera.at);
    if (objects.empty())
        throw Error("animation comet: scene " + base.name +
                    " has no small objects (parts of 100 triangles or more, at most 5% of the scene) to throw");
    const auto vertices = base.scene.vertices();
    const auto ids = object_vertices(base, objects.front());
    const Float3 centre = vertex_box(vertices, ids).center();
    const Box bounds = base.scene.bounds();
    const Float3 e = bounds.extent();
    // Across the scene: from near one lower corner to near the opposite one, in the upper half.
    const Float3 from = bounds.lower + Float3{0.1f * e.x, 0.6f * e.y, 0.2f * e.z};
    const Float3 to = bounds.lower + Float3{0.9f * e.x, 0.4f * e.y, 0.8f * e.z};
    std::vector<Float3> frames = repeated(vertices, 2);
    for (int k = 0; k < 2; ++k) {
        const Float3 shift = (k == 0 ? from : to) - centre;
        Float3* frame = frames.data() + std::size_t(k) * vertices.size();
        for (std::uint32_t v : ids) frame[v] = vertices[v] + shift;
    }
    const auto triangles =
        std::size_t(std::count(base.object_of_triangle.begin(), base.object_of_triangle.end(), objects.front()));
    return finish("comet", base,
                  "one object of " + base.name + " (" + std::to_string(triangles) + " triangles) flies across it",
                  uniform_times(2), frames, vertices.size(), base.scene.indices(), base.camera, base.camera);
}

AnimationSource make_party(const SceneSource& base, int spheres) {
    const auto vertices = base.scene.vertices();
    MeshBuilder ball;
    ball.add_tessellated_sphere({0, 0, 0}, 1.0f, kPartySphereSubdivisions);
    const Scene unit = ball.build();
    const auto ball_vertices = unit.vertices();
    const auto ball_indices = unit.indices();

    const Box bounds = base.scene.bounds();
    const Float3 e = bounds.extent();
    const float radius = 0.015f * bounds.diagonal();
    // Centres inside the box shrunk by 15% on each side (and by the radius).
    const Float3 lo = bounds.lower + e * 0.15f + Float3{radius, radius, radius};
    const Float3 span = e * 0.7f - Float3{2 * radius, 2 * radius, 2 * radius};
    DeterministicRandom random(std::uint32_t(spheres) * 7919u + 11u);
    std::vector<Float3> centres(std::size_t(spheres) * kPartyKeyframes);
    for (int s = 0; s < spheres; ++s) {
        Float3 c = lo + Float3{random.unit() * std::max(span.x, 0.0f), random.unit() * std::max(span.y, 0.0f),
                               random.unit() * std::max(span.z, 0.0f)};
        for (int k = 0; k < kPartyKeyframes; ++k) {
            centres[std::size_t(s) * kPartyKeyframes + std::size_t(k)] = c;
            // A drift of up to 12% of the box per keyframe step, kept inside.
            for (int a = 0; a < 3; ++a) {
                const float step = random.uniform(-0.12f, 0.12f) * (a == 0 ? e.x : a == 1 ? e.y : e.z);
                const float l = a == 0 ? lo.x : a == 1 ? lo.y : lo.z, w = a == 0 ? span.x : a == 1 ? span.y : span.z;
                coordinate(c, a) = std::clamp(coordinate(c, a) + step, l, l + std::max(w, 0.0f));
            }
        }
    }

    const std::size_t n = vertices.size() + std::size_t(spheres) * ball_vertices.size();
    std::vector<Float3> frames;
    frames.reserve(n * kPartyKeyframes);
    for (int k = 0; k < kPartyKeyframes; ++k) {
        frames.insert(frames.end(), vertices.begin(), vertices.end());
        for (int s = 0; s < spheres; ++s) {
            const Float3 c = centres[std::size_t(s) * kPartyKeyframes + std::size_t(k)];
            for (const Float3& v : ball_vertices) frames.push_back(c + v * radius);
        }
    }
    std::vector<std::uint32_t> indices(base.scene.indices().begin(), base.scene.indices().end());
    for (int s = 0; s < spheres; ++s) {
        const auto offset = std::uint32_t(vertices.size() + std::size_t(s) * ball_vertices.size());
        for (std::uint32_t i : ball_indices) indices.push_back(offset + i);
    }
    return finish("party:" + std::to_string(spheres), base,
                  std::to_string(spheres) + " spheres (" + std::to_string(ball_indices.size() / 3) +
                      " triangles each) drift through " + base.name,
                  uniform_times(kPartyKeyframes), frames, n, indices, base.camera, base.camera);
}

AnimationSource make_flythrough(const SceneSource& base) {
    const auto vertices = base.scene.vertices();
    const std::vector<Float3> frames = repeated(vertices, 2);
    // The end view: eye and target mirrored through the box centre along the horizontal axis nearest
    // the image's right, so the camera crosses the scene sideways at its height.
    Camera end = base.camera;
    const Float3 right = base.camera.basis().right;
    const float r[3] = {std::fabs(right.x), std::fabs(right.y), std::fabs(right.z)};
    const int axis = r[0] >= r[1] && r[0] >= r[2] ? 0 : (r[1] >= r[2] ? 1 : 2);
    Float3 centre = base.scene.bounds().center();
    coordinate(end.eye, axis) = 2.0f * coordinate(centre, axis) - coordinate(end.eye, axis);
    coordinate(end.at, axis) = 2.0f * coordinate(centre, axis) - coordinate(end.at, axis);
    return finish("flythrough", base, "the camera moves across " + base.name + "; nothing moves", uniform_times(2),
                  frames, vertices.size(), base.scene.indices(), base.camera, end);
}

}  // namespace

Camera AnimationSource::camera(float t) const {
    const float w = std::clamp(t, 0.0f, 1.0f);
    Camera c = camera_start;
    c.eye = camera_start.eye + (camera_end.eye - camera_start.eye) * w;
    c.at = camera_start.at + (camera_end.at - camera_start.at) * w;
    return c;
}

std::vector<std::uint32_t> small_objects(const SceneSource& source, Float3 target) {
    const auto& of = source.object_of_triangle;
    if (of.empty()) return {};
    const std::uint32_t objects = *std::max_element(of.begin(), of.end()) + 1;
    std::vector<std::size_t> count(objects, 0);
    std::vector<Box> boxes(objects);
    for (std::size_t t = 0; t < of.size(); ++t) {
        ++count[of[t]];
        const Triangle tri = source.scene.triangle(std::uint32_t(t));
        boxes[of[t]].extend(tri.v0);
        boxes[of[t]].extend(tri.v1);
        boxes[of[t]].extend(tri.v2);
    }
    std::vector<std::uint32_t> small;
    for (std::uint32_t o = 0; o < objects; ++o)
        if (count[o] >= kSmallObjectMinTriangles && double(count[o]) <= kSmallObjectMaxFraction * double(of.size()))
            small.push_back(o);
    std::stable_sort(small.begin(), small.end(), [&](std::uint32_t a, std::uint32_t b) {
        const Float3 da = boxes[a].center() - target, db = boxes[b].center() - target;
        return dot(da, da) < dot(db, db);
    });
    return small;
}

AnimationSource make_animation(const std::string& spec, const SceneSource& base) {
    const std::size_t colon = spec.find(':');
    const std::string name = spec.substr(0, colon);
    const bool has_parameter = colon != std::string::npos;
    if (name == "party") {
        const std::string p = has_parameter ? spec.substr(colon + 1) : std::string("8");
        int spheres = 0;
        std::size_t used = 0;
        try {
            spheres = std::stoi(p, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used != p.size() || p.empty() || spheres < 1 || spheres > kMaxPartySpheres)
            throw Error("animation " + spec + ": party:N needs a sphere count N in 1.." +
                        std::to_string(kMaxPartySpheres) + ", not '" + p + "'");
        return make_party(base, spheres);
    }
    if (has_parameter)
        throw Error("animation " + spec + ": " + name + " takes no parameter (animations: " + animation_spec_help() + ")");
    if (name == "spin") return make_spin(base);
    if (name == "comet") return make_comet(base);
    if (name == "flythrough") return make_flythrough(base);
    throw Error("animation '" + spec + "' is unknown (animations: " + animation_spec_help() + ")");
}

std::string animation_spec_help() { return "spin, comet, party:N (N spheres, 1..256, default 8), flythrough"; }

}  // namespace beamtrace::scenes
