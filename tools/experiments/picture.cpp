#include "experiments/picture.hpp"

#include <algorithm>
#include <cmath>

#include "beamtrace/error.hpp"
#include "report/colormap.hpp"

namespace beamtrace::workload {

Shade parse_shade(const std::string& text) {
    if (text == "normal") return Shade::normal;
    if (text == "depth") return Shade::depth;
    if (text == "ao") return Shade::ao;
    if (text == "complexity") return Shade::complexity;
    throw Error("unknown shading '" + text + "' (expected normal, depth, ao or complexity)");
}

namespace {

report::Image complexity_picture(const Engine& engine, const RaySet& primary) {
    std::vector<TileInfo> tiles;
    if (!engine.tile_complexity(primary, tiles))
        throw Error("--shade complexity needs an engine that traces beams of tiles (mlrta), not " + engine.name());
    report::Image image(primary.width, primary.height);
    double most = 1.0;
    for (const TileInfo& t : tiles) most = std::max(most, std::log2(double(std::max<std::size_t>(t.subtree_nodes, 1))));
    for (const TileInfo& t : tiles) {
        report::Rgb8 c{32, 32, 40};
        if (t.divergent)
            c = report::Rgb8{220, 30, 30};
        else if (t.subtree_nodes > 0)
            c = report::heat_color(std::log2(double(t.subtree_nodes)) / most);
        for (int y = t.y0 * 4; y < std::min(t.y1 * 4, primary.height); ++y)
            for (int x = t.x0 * 4; x < std::min(t.x1 * 4, primary.width); ++x) {
                const bool border = !t.divergent && (x == t.x0 * 4 || y == t.y0 * 4);
                const report::Rgb8 p =
                    border ? report::Rgb8{std::uint8_t(c.r / 2), std::uint8_t(c.g / 2), std::uint8_t(c.b / 2)} : c;
                image.set(x, y, p.r, p.g, p.b);
            }
    }
    return image;
}

}  // namespace

report::Image render_picture(const Engine& engine, const Scene& scene, const scenes::Camera& camera,
                             const PictureOptions& o) {
    const RaySet primary = make_primary_rays(camera, o.width, o.height);
    if (o.shade == Shade::complexity) return complexity_picture(engine, primary);
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
        case Shade::complexity:
            break;  // handled above
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
                if (primary.active(s) && hits[s].hit())
                    paint(primary.pixel[s], report::heat_color(1.0 - (hits[s].t - lo) / std::max(hi - lo, 1e-30f)));
            break;
        }
        case Shade::ao: {
            const RaySet ao = make_ao_rays(scene, primary, hits, o.ao_rays, o.ao_directions);
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
