#include "rays/ray_set.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "beamtrace/error.hpp"
#include "beamtrace/vlf.hpp"

namespace beamtrace::workload {

const char* to_string(Mode mode) {
    switch (mode) {
        case Mode::primary:
            return "primary";
        case Mode::shadow:
            return "shadow";
        case Mode::ao:
            return "ao";
        case Mode::diffuse:
            return "diffuse";
    }
    return "?";
}

Mode parse_mode(const std::string& text) {
    for (Mode m : {Mode::primary, Mode::shadow, Mode::ao, Mode::diffuse})
        if (text == to_string(m)) return m;
    throw Error("unknown mode '" + text + "' (expected primary, shadow, ao or diffuse)");
}

const char* to_string(Order order) { return order == Order::input ? "input" : "shuffled"; }

Order parse_order(const std::string& text) {
    for (Order o : {Order::input, Order::shuffled})
        if (text == to_string(o)) return o;
    throw Error("unknown order '" + text + "' (expected input or shuffled)");
}

RaySet make_primary_rays(const scenes::Camera& camera, int width, int height) {
    if (width <= 0 || height <= 0 || width > 65536 || height > 65536)
        throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) +
                    " is out of range (1 to 65536 on each side)");
    camera.validate();
    RaySet set;
    set.mode = Mode::primary;
    set.width = width;
    set.height = height;
    const int bx = (width + 3) / 4, by = (height + 3) / 4;
    set.packets_x = bx;
    set.packets_y = by;
    set.packets.resize(std::size_t(bx) * std::size_t(by));
    set.pixel.assign(set.packets.size() * 16, kNoPixel);
    for (int ty = 0; ty < by; ++ty)
        for (int tx = 0; tx < bx; ++tx) {
            const std::size_t p = std::size_t(ty) * std::size_t(bx) + std::size_t(tx);
            Packet16& packet = set.packets[p];
            packet.active = 0;
            for (int lane = 0; lane < 16; ++lane) {
                const int x = tx * 4 + lane % 4, y = ty * 4 + lane / 4;
                const bool inside = x < width && y < height;
                // Lanes outside the image repeat a valid ray so that they hold sane values.
                packet.set_ray(lane, camera.primary_ray(inside ? x : std::min(x, width - 1),
                                                        inside ? y : std::min(y, height - 1), width, height));
                if (inside) {
                    packet.active |= 1u << lane;
                    set.pixel[p * 16 + std::size_t(lane)] = std::uint32_t(y) * std::uint32_t(width) + std::uint32_t(x);
                    ++set.ray_count;
                }
            }
        }
    return set;
}

SurfacePoint surface_point(const Scene& scene, const Ray& ray, const Hit& hit) {
    const Triangle& t = scene.triangle(hit.triangle);
    SurfacePoint s;
    s.position = t.v0 * (1.0f - hit.u - hit.v) + t.v1 * hit.u + t.v2 * hit.v;
    Float3 n = cross(t.v1 - t.v0, t.v2 - t.v0);
    if (dot(n, ray.dir) > 0.0f) n = n * -1.0f;
    s.normal = normalize(n);
    return s;
}

float surface_offset(const Scene& scene) { return 1e-4f * scene.bounds().diagonal(); }

Float3 default_light(const scenes::Camera& camera, const Box& bounds) { return (camera.eye + bounds.center()) * 0.5f; }

namespace {

// Fills packets lane by lane; a packet is closed when full or when the caller asks.
class PacketWriter {
public:
    explicit PacketWriter(RaySet& set) : set_(set) {}
    void add(const Ray& ray, std::uint32_t pixel) {
        if (lane_ == 16 || set_.packets.empty()) start_packet();
        Packet16& p = set_.packets.back();
        p.set_ray(lane_, ray);
        p.active |= 1u << lane_;
        set_.pixel[(set_.packets.size() - 1) * 16 + std::size_t(lane_)] = pixel;
        ++lane_;
        ++set_.ray_count;
    }
    void close() { lane_ = 16; }
    // Room for this many packets, so that a set of hundreds of MB grows once instead of by doubling
    // (each doubling copies the set and holds both copies for a moment).
    void reserve(std::size_t packets) {
        set_.packets.reserve(packets);
        set_.pixel.reserve(packets * 16);
    }

private:
    void start_packet() {
        Packet16 p;
        p.active = 0;
        const Ray idle{{0, 0, 0}, 0.0f, {0, 0, 1}, 0.0f};
        for (int i = 0; i < 16; ++i) p.set_ray(i, idle);
        set_.packets.push_back(p);
        set_.pixel.resize(set_.packets.size() * 16, kNoPixel);
        lane_ = 0;
    }
    RaySet& set_;
    int lane_ = 16;
};

void check_hits(const RaySet& primary, const std::vector<Hit>& hits) {
    if (hits.size() != primary.slots()) throw Error("secondary rays: primary hits do not match the primary rays");
}

// A deterministic hash for per-pixel random numbers (independent of threads and engines).
std::uint32_t hash(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}
float unit_float(std::uint32_t h) { return float(h >> 8) * (1.0f / 16777216.0f); }

// The set's direction nearest to d, pointing d's way along its line.
Float3 snap_to_set(const DirectionSet& set, Float3 d) {
    const DirectionSet::Nearest near = set.nearest(d);
    const Float3 w = set.direction(int(near.index));
    return near.reversed ? w * -1.0f : w;
}

// An AO direction of the set, inside the hemisphere of n: the one nearest to the sample d, or, if
// that one lies below the horizon, the nearest to a fresh cosine-weighted sample (a few tries), or
// finally the set's direction nearest to n itself.
Float3 psf_direction(const DirectionSet& set, Float3 d, Float3 n, std::uint32_t h) {
    Float3 w = snap_to_set(set, d);
    const Float3 a = std::fabs(n.x) > 0.5f ? Float3{0, 1, 0} : Float3{1, 0, 0};
    const Float3 t = normalize(cross(a, n)), b = cross(n, t);
    for (std::uint32_t attempt = 1; dot(w, n) <= 0.0f && attempt <= 16; ++attempt) {
        const std::uint32_t g = hash(h + attempt * 0x9e3779b9u);
        const float u1 = unit_float(g), r = std::sqrt(u1), phi = 6.28318531f * unit_float(hash(g));
        const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
        w = snap_to_set(set, normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * z));
    }
    return dot(w, n) > 0.0f ? w : snap_to_set(set, n);
}

// An orthonormal frame around the unit normal n: t, b, n.
struct Frame {
    Float3 t, b, n;
};
Frame frame_around(Float3 n) {
    const Float3 a = std::fabs(n.x) > 0.5f ? Float3{0, 1, 0} : Float3{1, 0, 0};
    const Float3 t = normalize(cross(a, n));
    return Frame{t, cross(n, t), n};
}

// The cosine-weighted direction of the hemisphere of n for the uniform numbers u1, u2 in [0, 1).
Float3 cosine_direction(const Frame& f, float u1, float u2) {
    const float r = std::sqrt(u1), phi = 6.28318531f * u2;
    const float x = r * std::cos(phi), y = r * std::sin(phi), z = std::sqrt(std::max(0.0f, 1.0f - u1));
    return normalize(f.t * x + f.b * y + f.n * z);
}
Float3 cosine_direction(Float3 n, float u1, float u2) { return cosine_direction(frame_around(n), u1, u2); }

// The shadow ray from a surface point to a light: from the point lifted off the surface towards
// the light, ending just before it (tfar = 1 - 1e-4 with the direction light - origin). False when
// the light sits on the point.
bool shadow_ray(const SurfacePoint& s, Float3 light, float offset, Ray& r) {
    const Float3 to_light = light - s.position;
    const Float3 lift = s.normal * (dot(s.normal, to_light) >= 0.0f ? offset : -offset);
    r.org = s.position + lift;
    r.dir = light - r.org;
    if (!(dot(r.dir, r.dir) > 0.0f)) return false;
    r.tnear = 0.0f;
    r.tfar = 1.0f - 1e-4f;
    return true;
}

// Shadow rays in the primary rays' slots (an image when they are one), one per primary hit, to the
// point light_of(pixel).
template <class LightOf>
RaySet image_shadow_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& hits, LightOf&& light_of) {
    check_hits(primary, hits);
    RaySet set;
    set.mode = Mode::shadow;
    set.width = primary.width;
    set.height = primary.height;
    const float offset = surface_offset(scene);
    set.packets_x = primary.packets_x;
    set.packets_y = primary.packets_y;
    set.packets.resize(primary.packets.size());
    set.pixel.assign(primary.slots(), kNoPixel);
    const Ray idle{{0, 0, 0}, 0.0f, {0, 0, 1}, 0.0f};
    for (std::size_t p = 0; p < primary.packets.size(); ++p) {
        Packet16& packet = set.packets[p];
        packet.active = 0;
        for (int lane = 0; lane < 16; ++lane) {
            packet.set_ray(lane, idle);
            const std::size_t slot = p * 16 + std::size_t(lane);
            if (!primary.active(slot) || !hits[slot].hit()) continue;
            const SurfacePoint s = surface_point(scene, primary.ray(slot), hits[slot]);
            Ray r;
            if (!shadow_ray(s, light_of(primary.pixel[slot]), offset, r)) continue;  // the light sits on the point
            packet.set_ray(lane, r);
            packet.active |= 1u << lane;
            set.pixel[slot] = primary.pixel[slot];
            ++set.ray_count;
        }
    }
    return set;
}

// The radical inverse of i in base b (the Halton sequence).
float radical_inverse(std::uint32_t i, std::uint32_t b) {
    double f = 1.0, r = 0.0;
    for (; i > 0; i /= b) {
        f /= double(b);
        r += f * double(i % b);
    }
    return float(r);
}

// SplitMix64: the generator of the shuffle.
std::uint64_t splitmix64(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

}  // namespace

RaySet make_random_rays(const Box& box, std::size_t count, unsigned seed, Mode mode) {
    RaySet set;
    set.mode = mode;
    set.width = int(std::min<std::size_t>(count, 65536));
    set.height = 1;
    PacketWriter writer(set);
    const Float3 lo = box.lower - box.extent() * 0.2f, size = box.extent() * 1.4f;
    for (std::size_t i = 0; i < count; ++i) {
        auto u = [&](std::uint32_t k) { return unit_float(hash(std::uint32_t(i) * 13u + k + seed * 7777u)); };
        Ray r;
        r.org = lo + Float3{u(1) * size.x, u(2) * size.y, u(3) * size.z};
        const float z = 2.0f * u(4) - 1.0f, phi = 6.28318531f * u(5), s = std::sqrt(std::max(0.0f, 1.0f - z * z));
        r.dir = Float3{s * std::cos(phi), s * std::sin(phi), z};
        r.tfar = closest_hit(mode) ? kInfinity : 0.5f * box.diagonal();
        writer.add(r, std::uint32_t(i % std::size_t(set.width)));
    }
    return set;
}

RaySet make_shadow_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& hits, Float3 light) {
    return image_shadow_rays(scene, primary, hits, [light](std::uint32_t) { return light; });
}

RaySet make_area_shadow_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& hits,
                             const AreaLight& light) {
    return image_shadow_rays(scene, primary, hits, [&light](std::uint32_t pixel) {
        const std::uint32_t h = hash(pixel * 7919u + 0x1b873593u);
        return light.point(unit_float(h), unit_float(hash(h)));
    });
}

namespace {

// The rays a mode makes from each primary hit, in pixel order: per_hit(point, pixel, writer) adds
// that hit's rays (and may close the packet first, to start a pixel's rays in a packet of their own).
// rays_per_hit: the most rays per_hit adds for one hit (what the set reserves).
template <class PerHit>
RaySet rays_from_hits(const Scene& scene, const RaySet& primary, const std::vector<Hit>& hits, Mode mode,
                      std::size_t rays_per_hit, PerHit&& per_hit) {
    RaySet set;
    set.mode = mode;
    set.width = primary.width;
    set.height = primary.height;
    PacketWriter writer(set);
    std::size_t hit_count = 0;
    for (std::size_t slot = 0; slot < primary.slots(); ++slot) hit_count += primary.active(slot) && hits[slot].hit();
    // per_hit closes packets only when its rays fill whole ones, so the rays pack densely.
    writer.reserve((hit_count * rays_per_hit + 15) / 16 + 1);
    for (std::size_t slot = 0; slot < primary.slots(); ++slot) {
        if (!primary.active(slot) || !hits[slot].hit()) continue;
        per_hit(surface_point(scene, primary.ray(slot), hits[slot]), primary.pixel[slot], writer);
    }
    return set;
}

}  // namespace

RaySet make_shadow_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& hits,
                        const std::vector<Float3>& lights) {
    check_hits(primary, hits);
    if (lights.empty() || lights.size() > 4096) throw Error("--lights must be between 1 and 4096");
    const float offset = surface_offset(scene);
    return rays_from_hits(scene, primary, hits, Mode::shadow, lights.size(),
                          [&](const SurfacePoint& s, std::uint32_t pixel, PacketWriter& writer) {
                              if (lights.size() >= 16 && lights.size() % 16 == 0) writer.close();
                              for (const Float3& light : lights) {
                                  Ray r;
                                  if (shadow_ray(s, light, offset, r)) writer.add(r, pixel);
                              }
                          });
}

RaySet make_diffuse_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& hits) {
    check_hits(primary, hits);
    const float offset = surface_offset(scene);
    return rays_from_hits(scene, primary, hits, Mode::diffuse, 1,
                          [&](const SurfacePoint& s, std::uint32_t pixel, PacketWriter& writer) {
                              const std::uint32_t h = hash(pixel * 7919u + 0x68e31da4u);
                              Ray ray;
                              ray.org = s.position + s.normal * offset;
                              ray.dir = cosine_direction(s.normal, unit_float(h), unit_float(hash(h)));
                              ray.tnear = 0.0f;
                              ray.tfar = kInfinity;
                              writer.add(ray, pixel);
                          });
}

AoDirections::Source parse_ao_directions(const std::string& text) {
    if (text == "random") return AoDirections::Source::random;
    if (text == "psf") return AoDirections::Source::psf;
    throw Error("unknown AO directions '" + text + "' (expected random or psf)");
}

RaySet make_ao_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& hits, int ao_rays,
                    const AoDirections& directions) {
    check_hits(primary, hits);
    const std::unique_ptr<DirectionSet> psf = directions.source == AoDirections::Source::psf
                                                  ? std::make_unique<DirectionSet>(directions.psf_directions)
                                                  : nullptr;
    if (ao_rays <= 0 || ao_rays > 4096) throw Error("--ao-rays must be between 1 and 4096");
    const float offset = surface_offset(scene), length = 0.1f * scene.bounds().diagonal();
    const int strata = int(std::sqrt(double(ao_rays)));
    return rays_from_hits(scene, primary, hits, Mode::ao, std::size_t(ao_rays), [&](const SurfacePoint& s, std::uint32_t pixel, PacketWriter& writer) {
        const Frame f = frame_around(s.normal);  // an orthonormal frame around the normal
        if (ao_rays >= 16 && ao_rays % 16 == 0) writer.close();
        for (int i = 0; i < ao_rays; ++i) {
            const std::uint32_t h = hash(pixel * 7919u + std::uint32_t(i) * 104729u + 17u);
            float u1 = unit_float(h), u2 = unit_float(hash(h));
            if (i < strata * strata) {  // stratified over a strata x strata grid, the rest plain random
                u1 = (float(i % strata) + u1) / float(strata);
                u2 = (float(i / strata) + u2) / float(strata);
            }
            Ray ray;
            ray.org = s.position + s.normal * offset;
            ray.dir = cosine_direction(f, u1, u2);
            if (psf) ray.dir = psf_direction(*psf, ray.dir, s.normal, h);
            ray.tnear = 0.0f;
            ray.tfar = length;
            writer.add(ray, pixel);
        }
    });
}

Float3 UpperBox::up() const {
    Float3 u{0, 0, 0};
    u[up_axis] = up_sign;
    return u;
}

UpperBox upper_box(const Box& bounds, Float3 up) {
    if (bounds.empty() || !(bounds.diagonal() < kInfinity))
        throw Error("lights: the scene's box is empty or unbounded");
    UpperBox u;
    int axis = 1;  // y, then z, then x on ties
    for (int k : {2, 0})
        if (std::fabs(up[k]) > std::fabs(up[axis])) axis = k;
    u.up_axis = axis;
    u.up_sign = up[axis] < 0.0f ? -1.0f : 1.0f;
    const Float3 e = bounds.extent();
    u.box = bounds;
    for (int k = 0; k < 3; ++k) {
        u.box.lower[k] = bounds.lower[k] + 0.05f * e[k];
        u.box.upper[k] = bounds.upper[k] - 0.05f * e[k];
    }
    if (u.up_sign > 0.0f)
        u.box.lower[axis] = bounds.upper[axis] - 0.20f * e[axis];
    else
        u.box.upper[axis] = bounds.lower[axis] + 0.20f * e[axis];
    return u;
}

namespace {
// The two axes across up, in x, y, z order.
std::pair<int, int> across(int up_axis) { return {up_axis == 0 ? 1 : 0, up_axis == 2 ? 1 : 2}; }
}  // namespace

std::vector<Float3> spread_lights(const UpperBox& upper, int count) {
    if (count < 1 || count > 4096) throw Error("--lights must be between 1 and 4096");
    const auto [h1, h2] = across(upper.up_axis);
    const Float3 lo = upper.box.lower, e = upper.box.extent();
    std::vector<Float3> lights;
    for (int i = 0; i < count; ++i) {
        const auto n = std::uint32_t(i + 1);
        Float3 p = lo;
        p[h1] += radical_inverse(n, 2) * e[h1];
        p[h2] += radical_inverse(n, 3) * e[h2];
        p[upper.up_axis] += radical_inverse(n, 5) * e[upper.up_axis];
        lights.push_back(p);
    }
    return lights;
}

AreaLight area_light(const UpperBox& upper) {
    const auto [h1, h2] = across(upper.up_axis);
    const Float3 e = upper.box.extent();
    AreaLight a;
    a.side = 0.5f * std::min(e[h1], e[h2]);
    a.center = upper.box.center();
    a.center[upper.up_axis] = upper.up_sign > 0.0f ? upper.box.upper[upper.up_axis] : upper.box.lower[upper.up_axis];
    a.edge_u = Float3{0, 0, 0};
    a.edge_v = Float3{0, 0, 0};
    a.edge_u[h1] = a.side;
    a.edge_v[h2] = a.side;
    return a;
}

RaySet reorder(const RaySet& rays, Order order) {
    if (order == Order::input) return rays;
    std::vector<std::uint32_t> slots;
    slots.reserve(rays.ray_count);
    for (std::size_t slot = 0; slot < rays.slots(); ++slot)
        if (rays.active(slot)) slots.push_back(std::uint32_t(slot));
    std::uint64_t state = kShuffleSeed;
    for (std::size_t i = slots.size(); i > 1; --i) {  // Fisher-Yates: position i - 1 takes one of [0, i)
        const std::size_t j = std::size_t(splitmix64(state) % i);
        std::swap(slots[i - 1], slots[j]);
    }
    RaySet set;
    set.mode = rays.mode;
    set.width = rays.width;
    set.height = rays.height;
    PacketWriter writer(set);
    for (const std::uint32_t slot : slots) writer.add(rays.ray(slot), rays.pixel[slot]);
    return set;
}

}  // namespace beamtrace::workload
