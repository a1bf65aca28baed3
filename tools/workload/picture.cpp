#include "workload/picture.hpp"

#include <algorithm>
#include <cmath>

#include "beamtrace/error.hpp"
#include "report/colormap.hpp"

namespace beamtrace::workload {

Shade parse_shade(const std::string& text) {
    if (text == "normal") return Shade::normal;
    if (text == "depth") return Shade::depth;
    if (text == "ao") return Shade::ao;
    throw Error("unknown shading '" + text + "' (expected normal, depth or ao)");
}

report::Image render_picture(const Engine& engine, const Scene& scene, const scenes::Camera& camera,
                             const PictureOptions& o) {
    const RaySet primary = make_primary_rays(camera, o.width, o.height);
    std::vector<Hit> hits;
    engine.intersect(primary, hits, o.threads);
    report::Image image(o.width, o.height);
    const report::Rgb8 background{32, 32, 40};
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) image.set(x, y, background.r, background.g, background.b);

    auto paint = [&](std::uint32_t pixel, report::Rgb8 c) {
        image.set(int(pixel % std::uint32_t(o.width)), int(pixel / std::uint32_t(o.width)), c.r, c.g, c.b);
    };
    switch (o.shade) {
        case Shade::normal:
            for (std::size_t s = 0; s < primary.slots(); ++s)
                if (primary.active(s) && hits[s].hit())
                    paint(primary.pixel[s], report::normal_color(surface_point(scene, primary.ray(s), hits[s]).normal));
            break;
        case Shade::depth: {
            float lo = kInfinity, hi = 0.0f;
            for (const Hit& h : hits)
                if (h.hit()) lo = std::min(lo, h.t), hi = std::max(hi, h.t);
            for (std::size_t s = 0; s < primary.slots(); ++s)
                if (primary.active(s) && hits[s].hit()) paint(primary.pixel[s], report::heat_color(1.0 - (hits[s].t - lo) / std::max(hi - lo, 1e-30f)));
            break;
        }
        case Shade::ao: {
            const RaySet ao = make_ao_rays(scene, primary, hits, o.ao_rays);
            std::vector<std::uint8_t> occluded;
            engine.occluded(ao, occluded, o.threads);
            std::vector<int> open(std::size_t(o.width) * std::size_t(o.height), 0);
            std::vector<int> total(open.size(), 0);
            for (std::size_t s = 0; s < ao.slots(); ++s)
                if (ao.active(s)) {
                    ++total[ao.pixel[s]];
                    open[ao.pixel[s]] += occluded[s] ? 0 : 1;
                }
            for (std::size_t p = 0; p < open.size(); ++p)
                if (total[p] > 0) {
                    const auto v = std::uint8_t(std::lround(255.0 * open[p] / total[p]));
                    paint(std::uint32_t(p), report::Rgb8{v, v, v});
                }
            break;
        }
    }
    return image;
}

}  // namespace beamtrace::workload
