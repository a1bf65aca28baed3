#include "extremes/placement.hpp"

#include <cmath>
#include <cstdio>
#include <vector>

namespace beamtrace::test {

Float3 Placement::point(Float3 p) const {
    return {float(double(p.x) * scale + offset[0]), float(double(p.y) * scale + offset[1]),
            float(double(p.z) * scale + offset[2])};
}

Float3 Placement::direction(Float3 d) const {
    if (unit_directions) return normalize(d);
    return {float(double(d.x) * scale), float(double(d.y) * scale), float(double(d.z) * scale)};
}

Ray Placement::ray(const Ray& r) const {
    if (!unit_directions) return Ray{point(r.org), r.tnear, direction(r.dir), r.tfar};
    // t measured along the unit direction: multiply by the direction's new length.
    const double length = std::sqrt(double(r.dir.x) * r.dir.x + double(r.dir.y) * r.dir.y + double(r.dir.z) * r.dir.z);
    const double factor = scale * length;
    return Ray{point(r.org), float(r.tnear * factor), direction(r.dir), float(r.tfar * factor)};
}

scenes::SceneSource placed(const scenes::SceneSource& source, const Placement& placement) {
    std::vector<Float3> vertices;
    for (const Float3& v : source.scene.vertices()) vertices.push_back(placement.point(v));
    const auto indices = source.scene.indices();
    char name[160];
    std::snprintf(name, sizeof name, "%s x%g +(%g,%g,%g)%s", source.name.c_str(), placement.scale, placement.offset[0],
                  placement.offset[1], placement.offset[2], placement.unit_directions ? " unit directions" : "");
    Scene scene(std::span<const Float3>(vertices), indices);
    scenes::Camera camera = source.camera;
    camera.eye = placement.point(camera.eye);
    camera.at = placement.point(camera.at);
    // Far from the origin the eye and the point looked at may round to one point.
    if (camera.eye == camera.at) camera = scenes::frame_from_outside(scene.bounds());
    return scenes::SceneSource{name, std::move(scene), camera, source.description};
}

workload::RaySet placed(const workload::RaySet& rays, const Placement& placement) {
    workload::RaySet out = rays;
    for (Packet16& p : out.packets)
        for (int i = 0; i < 16; ++i) p.set_ray(i, placement.ray(p.ray(i)));
    return out;
}

}  // namespace beamtrace::test
