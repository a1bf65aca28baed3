#pragma once
// Pictures of what an engine sees: surface normals, depth, or ambient occlusion.
#include <string>

#include "report/png_image.hpp"
#include "workload/engine.hpp"
#include "scenes/camera.hpp"

namespace beamtrace::workload {

enum class Shade { normal, depth, ao };
Shade parse_shade(const std::string& text);  // throws beamtrace::Error naming the choices

struct PictureOptions {
    Shade shade = Shade::normal;
    int width = 1024, height = 1024;
    int threads = 1;
    int ao_rays = 16;
};

// Traces the primary rays (and, for ao, the AO rays from the engine's own hits) with `engine`,
// which must already be built for `scene`.
report::Image render_picture(const Engine& engine, const Scene& scene, const scenes::Camera& camera,
                             const PictureOptions& options);

}  // namespace beamtrace::workload
