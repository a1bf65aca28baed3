// Pinhole camera, its parsers, and the automatic framing of a box.
#include "scenes/camera.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string_view>

#include "beamtrace/error.hpp"
#include "scenes/text_fields.hpp"

namespace beamtrace::scenes {

namespace {

bool finite(Float3 p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

std::string text(Float3 p) {
    std::ostringstream s;
    s << "(" << p.x << "," << p.y << "," << p.z << ")";
    return s.str();
}

void check_fov(float fovy_degrees, const std::string& what) {
    if (!(fovy_degrees > 0.0f && fovy_degrees < 180.0f))
        throw Error(what + ": field FOVY must be in (0,180) degrees, got " + std::to_string(fovy_degrees));
}

}  // namespace

void Camera::validate() const {
    if (!finite(eye) || !finite(at) || !finite(up) || !std::isfinite(fovy_degrees))
        throw Error("camera: eye, at, up and fovy must be finite numbers");
    if (eye == at) throw Error("camera: eye and at are the same point " + text(eye));
    check_fov(fovy_degrees, "camera");
}

Camera::Basis Camera::basis() const {
    const Float3 forward = normalize(at - eye);
    Float3 right = cross(forward, up);
    const float up_length = length(up);
    if (!(length(right) > 1e-6f * up_length)) {
        // Looking along `up` (or no up given): use the world axis least aligned with the view.
        const std::array<Float3, 3> axes{Float3{0, 1, 0}, Float3{0, 0, 1}, Float3{1, 0, 0}};
        Float3 best = axes[0];
        for (const Float3& a : axes)
            if (std::fabs(dot(a, forward)) < std::fabs(dot(best, forward))) best = a;
        right = cross(forward, best);
    }
    right = normalize(right);
    return Basis{forward, right, cross(right, forward)};
}

Ray Camera::primary_ray(int px, int py, int width, int height) const {
    validate();
    if (width <= 0 || height <= 0)
        throw Error("camera: image size " + std::to_string(width) + "x" + std::to_string(height) + " is empty");
    const Basis b = basis();
    const float tan_half = std::tan(fovy_degrees * (std::numbers::pi_v<float> / 360.0f));
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    const float sx = (2.0f * (static_cast<float>(px) + 0.5f) / static_cast<float>(width) - 1.0f) * tan_half * aspect;
    const float sy = (1.0f - 2.0f * (static_cast<float>(py) + 0.5f) / static_cast<float>(height)) * tan_half;
    return Ray{eye, 0.0f, normalize(b.forward + b.right * sx + b.up * sy), kInfinity};
}

Camera parse_camera(const std::string& text_in, const std::string& what) {
    static constexpr std::array<std::string_view, 7> names{"EX", "EY", "EZ", "AX", "AY", "AZ", "FOVY"};
    const std::vector<float> v = parse_numbers(text_in, names, what);
    Camera c;
    c.eye = {v[0], v[1], v[2]};
    c.at = {v[3], v[4], v[5]};
    c.fovy_degrees = v[6];
    if (c.eye == c.at) throw Error(what + ": eye (EX,EY,EZ) and at (AX,AY,AZ) are the same point " + text(c.eye));
    check_fov(c.fovy_degrees, what);
    return c;
}

std::string format_camera(const Camera& c) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", double(c.eye.x), double(c.eye.y),
                  double(c.eye.z), double(c.at.x), double(c.at.y), double(c.at.z), double(c.fovy_degrees));
    return buf;
}

Float3 parse_point(const std::string& text_in, const std::string& what) {
    static constexpr std::array<std::string_view, 3> names{"X", "Y", "Z"};
    const std::vector<float> v = parse_numbers(text_in, names, what);
    return {v[0], v[1], v[2]};
}

Camera frame_from_outside(const Box& bounds) {
    if (bounds.empty()) throw Error("camera: cannot frame an empty box");
    if (!finite(bounds.lower) || !finite(bounds.upper)) throw Error("camera: cannot frame a box with infinite bounds");
    Camera c;
    c.at = bounds.center();
    float radius = 0.5f * bounds.diagonal();  // bounding sphere of the box
    if (!(radius > 0.0f)) radius = 1.0f;      // a single point: any distance will do
    // From the front-right (+x, +z) and a little above (+y): the classic 3/4 view. Back off along that
    // direction until all 8 corners are inside the vertical field of view with a 5% margin on each
    // side (so inside a square or wider image), and at least 5% beyond the bounding sphere.
    const Float3 direction = normalize(Float3{0.6f, 0.45f, 0.8f});
    Camera axes;  // the same view axes, from a camera at the origin
    axes.eye = direction;
    axes.at = {0, 0, 0};
    const Camera::Basis b = axes.basis();
    const float tan_half = std::tan(c.fovy_degrees * (std::numbers::pi_v<float> / 360.0f)) / 1.05f;
    float distance = 1.05f * radius;
    for (int k = 0; k < 8; ++k) {
        const Float3 corner{(k & 1) ? bounds.upper.x : bounds.lower.x, (k & 2) ? bounds.upper.y : bounds.lower.y,
                            (k & 4) ? bounds.upper.z : bounds.lower.z};
        const Float3 offset = corner - c.at;
        // Depth of the corner seen from eye = at + direction * distance is distance + dot(offset, forward).
        const float sideways = std::max(std::fabs(dot(offset, b.right)), std::fabs(dot(offset, b.up)));
        distance = std::max(distance, sideways / tan_half - dot(offset, b.forward));
    }
    // Far from the origin a tiny box needs a distance that still changes the coordinates of `at`.
    const float magnitude = std::max({std::fabs(c.at.x), std::fabs(c.at.y), std::fabs(c.at.z)});
    distance = std::max(distance, 1e-4f * magnitude);
    c.eye = c.at + direction * distance;
    return c;
}

}  // namespace beamtrace::scenes
