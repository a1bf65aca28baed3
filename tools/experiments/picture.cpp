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
    if (text == "shadow") return Shade::shadow;
    if (text == "complexity") return Shade::complexity;
    throw Error("unknown shading '" + text + "' (expected normal, depth, ao, shadow or complexity)");
}

const char* to_string(Shade shade) {
    switch (shade) {
        case Shade::normal:
            return "normal";
        case Shade::depth:
            return "depth";
        case Shade::ao:
            return "ao";
        case Shade::shadow:
            return "shadow";
        case Shade::complexity:
            return "complexity";
    }
    return "?";
}

Mode picture_mode(const PictureOptions& o) {
    const std::string shade = to_string(o.shade), mode = to_string(o.mode);
    switch (o.mode) {
        case Mode::primary:
            break;
        case Mode::ao:
        case Mode::shadow:
            if ((o.mode == Mode::ao && o.shade != Shade::ao) || (o.mode == Mode::shadow && o.shade != Shade::shadow))
                throw Error("--mode " + mode + " draws --shade " + mode + ", not --shade " + shade);
            break;
        case Mode::diffuse:
            if (o.shade != Shade::normal && o.shade != Shade::depth)
                throw Error("--mode diffuse draws the bounce rays' hits by --shade normal or depth, not --shade " +
                            shade);
            break;
    }
    if (o.shade == Shade::ao) return Mode::ao;
    if (o.shade == Shade::shadow) return Mode::shadow;
    return o.mode;
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

WorkloadConfig picture_config(const PictureOptions& o) {
    WorkloadConfig config;
    config.mode = picture_mode(o);
    config.width = o.width;
    config.height = o.height;
    config.ao_rays = o.ao_rays;
    config.ao_directions = o.ao_directions;
    config.light = o.light;
    config.lights = o.lights;
    config.area_light = o.area_light;
    config.order = o.order;
    config.validate();
    if (o.shade == Shade::complexity && o.order != Order::input)
        throw Error("--shade complexity needs the rays in image order (--order input), not --order " +
                    std::string(to_string(o.order)));
    return config;
}

report::Image render_picture(const Engine& engine, const Scene& scene, const scenes::Camera& camera,
                             const PictureOptions& o) {
    const WorkloadConfig config = picture_config(o);
    const RaySet image = make_primary_rays(camera, o.width, o.height);
    if (o.shade == Shade::complexity) return complexity_picture(engine, image);
    // The primary rays are the picture's rays only in primary mode; secondary rays start from them in
    // image order and are put in the order asked for themselves.
    const RaySet primary = config.mode == Mode::primary ? reorder(image, o.order) : image;
    std::vector<Hit> hits;
    engine.intersect(primary, hits, o.threads);
    report::Image picture(o.width, o.height);
    const report::Rgb8 background{32, 32, 40};
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) picture.set(x, y, background.r, background.g, background.b);

    auto paint = [&](std::uint32_t pixel, report::Rgb8 c) {
        picture.set(int(pixel % std::uint32_t(o.width)), int(pixel / std::uint32_t(o.width)), c.r, c.g, c.b);
    };
    // Normal or depth of the closest hits of `rays`; rays that escape are painted `escaped` (if any).
    auto shade_hits = [&](const RaySet& rays, const std::vector<Hit>& closest, const report::Rgb8* escaped) {
        float lo = kInfinity, hi = 0.0f;
        for (const Hit& h : closest)
            if (h.hit()) lo = std::min(lo, h.t), hi = std::max(hi, h.t);
        for (std::size_t s = 0; s < rays.slots(); ++s) {
            if (!rays.active(s)) continue;
            if (!closest[s].hit()) {
                if (escaped) paint(rays.pixel[s], *escaped);
                continue;
            }
            paint(rays.pixel[s], o.shade == Shade::depth
                                     ? report::heat_color(1.0 - (closest[s].t - lo) / std::max(hi - lo, 1e-30f))
                                     : report::normal_color(surface_point(scene, rays.ray(s), closest[s]).normal));
        }
    };
    switch (config.mode) {
        case Mode::primary:
            shade_hits(primary, hits, nullptr);
            break;
        case Mode::diffuse: {
            const RaySet bounce = make_mode_rays(scene, primary, hits, config, {});
            std::vector<Hit> bounce_hits;
            engine.intersect(bounce, bounce_hits, o.threads);
            const report::Rgb8 sky{220, 230, 245};
            shade_hits(bounce, bounce_hits, &sky);
            break;
        }
        case Mode::ao:
        case Mode::shadow: {
            const RaySet rays =
                make_mode_rays(scene, primary, hits, config, shadow_lights(config, scene.bounds(), camera));
            std::vector<std::uint8_t> occluded;
            engine.occluded(rays, occluded, o.threads);
            std::vector<int> open(std::size_t(o.width) * std::size_t(o.height), 0);
            std::vector<int> total(open.size(), 0);
            for (std::size_t s = 0; s < rays.slots(); ++s)
                if (rays.active(s)) {
                    ++total[rays.pixel[s]];
                    open[rays.pixel[s]] += occluded[s] ? 0 : 1;
                }
            for (std::size_t p = 0; p < open.size(); ++p)
                if (total[p] > 0) {
                    const auto v = std::uint8_t(std::lround(255.0 * open[p] / total[p]));
                    paint(std::uint32_t(p), report::Rgb8{v, v, v});
                }
            break;
        }
    }
    return picture;
}

}  // namespace beamtrace::workload
