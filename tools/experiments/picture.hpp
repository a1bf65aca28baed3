#pragma once
// Pictures of what an engine sees: surface normals, depth, ambient occlusion, or (MLRTA) the
// geometric complexity of each tile: the size of the subtree below its entry point (Figure 7).
#include <string>

#include <optional>

#include "report/png_image.hpp"
#include "engines/engine.hpp"
#include "rays/workload.hpp"
#include "scenes/camera.hpp"

namespace beamtrace::workload {

enum class Shade { normal, depth, ao, shadow, complexity };
Shade parse_shade(const std::string& text);  // throws beamtrace::Error naming the choices
const char* to_string(Shade shade);

struct PictureOptions {
    Shade shade = Shade::normal;
    int width = 1024, height = 1024;
    int threads = 1;
    int ao_rays = 16;
    AoDirections ao_directions;  // random, or VLF-RT's PSF directions (the paper's Figure 8)
    // The rays, as for a workload (WorkloadConfig): primary or diffuse (shaded by normal or depth);
    // shade ao and shadow make ao and shadow rays. order applies to the rays the picture is made of
    // (the primary rays for normal and depth, else the secondary rays).
    Mode mode = Mode::primary;
    std::optional<Float3> light;  // shadow: the single light (default_light() unless given)
    int lights = 0;               // shadow: N lights over the upper box
    bool area_light = false;      // shadow: the area light
    Order order = Order::input;
};

// The mode of the rays a picture traces after its primary rays: ao for Shade::ao, shadow for
// Shade::shadow, else options.mode. Throws beamtrace::Error when shade and mode do not go together
// (--mode ao or shadow with another shade, --mode diffuse with a shade other than normal or depth).
Mode picture_mode(const PictureOptions& options);
// The rays of the picture as a workload's (mode picture_mode(), lights, order, ...), checked
// (WorkloadConfig::validate, picture_mode).
WorkloadConfig picture_config(const PictureOptions& options);

// Traces the primary rays (and the secondary rays of the picture's mode from the engine's own hits)
// with `engine`, which must already be built for `scene`; pixels are found through RaySet::pixel, so
// any order draws the same picture. normal / depth: of the closest hits (of the primary rays, or of
// the diffuse bounce rays, whose escapes are drawn in a pale sky colour). ao / shadow: the fraction of
// each pixel's rays that are not blocked, grey. Complexity: each tile in a heat colour of log2 of its
// entry point's subtree size (dark: a leaf), tiles whose rays diverge in sign in red, tiles whose
// rays certainly miss everything in the background colour; needs an engine that traces beams (mlrta)
// and rays in image order.
report::Image render_picture(const Engine& engine, const Scene& scene, const scenes::Camera& camera,
                             const PictureOptions& options);

}  // namespace beamtrace::workload
