#pragma once
// Pictures of what an engine sees: surface normals, depth, ambient occlusion, or (MLRTA) the
// geometric complexity of each tile: the size of the subtree below its entry point (Figure 7).
#include <string>

#include "report/png_image.hpp"
#include "engines/engine.hpp"
#include "scenes/camera.hpp"

namespace beamtrace::workload {

enum class Shade { normal, depth, ao, complexity };
Shade parse_shade(const std::string& text);  // throws beamtrace::Error naming the choices

struct PictureOptions {
    Shade shade = Shade::normal;
    int width = 1024, height = 1024;
    int threads = 1;
    int ao_rays = 16;
    AoDirections ao_directions;  // random, or VLF-RT's PSF directions (the paper's Figure 8)
};

// Traces the primary rays (and, for ao, the AO rays from the engine's own hits) with `engine`,
// which must already be built for `scene`. Complexity: each tile in a heat colour of log2 of its
// entry point's subtree size (dark: a leaf), tiles whose rays diverge in sign in red, tiles whose
// rays certainly miss everything in the background colour; needs an engine that traces beams (mlrta).
report::Image render_picture(const Engine& engine, const Scene& scene, const scenes::Camera& camera,
                             const PictureOptions& options);

}  // namespace beamtrace::workload
