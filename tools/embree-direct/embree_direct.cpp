// embree-direct: Embree 3 called directly, as its manual advises, on the camera rays of
// `beamtrace bench` (and the shadow rays it makes from their hits). It shares no code with beamtrace
// on purpose: it is the cross-check that the bench's Embree engines (the anchor of every ratio) are
// Embree at its best, and it cannot drift with the bench's code. docs/oracle.md says how to compare.
//
//   embree-direct --scene FILE.off [--camera EX,EY,EZ,AX,AY,AZ,FOVY] [--light X,Y,Z]
//                 [--width 1024] [--height 1024] [--repeats 5] [--non-robust] [--json FILE] [--dump PREFIX]
//
// The rays are the bench's, computed the same way (4x4 pixel packets; the bench's default camera
// and light when none is given); rays are written once into Embree's layouts, the timed region holds
// the rtc* calls only, and every layout is timed with both context flags (best of --repeats).
// --dump writes PREFIX.primary (per pixel, row-major: the hit triangle as uint32, 0xFFFFFFFF for a
// miss) and PREFIX.shadow (per pixel: 1 if the shadow ray is blocked, else 0; 0 where the primary
// ray missed).
#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

// ---- small vector maths (the same float operations, in the same order, as the bench's rays) ----
struct V3 {
    float x, y, z;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(V3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
float length(V3 a) { return std::sqrt(dot(a, a)); }
V3 normalize(V3 a) { return a * (1.0f / length(a)); }

struct Bounds {
    V3 lo{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
          std::numeric_limits<float>::infinity()};
    V3 hi{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
          -std::numeric_limits<float>::infinity()};
    void add(V3 p) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    V3 center() const { return (lo + hi) * 0.5f; }
    float diagonal() const { return length(hi - lo); }
};

// ---- the mesh: an OFF file, polygons as fans ----
struct Mesh {
    std::vector<V3> vertices;
    std::vector<std::uint32_t> indices;
    Bounds bounds;  // of the triangles' corners
};

Mesh load_off(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot open '" + path + "'");
    std::vector<std::string> tokens;
    std::string line;
    // Tokens of the next line that holds any ('#' starts a comment).
    const auto next = [&]() {
        while (std::getline(in, line)) {
            line = line.substr(0, line.find('#'));
            std::istringstream s(line);
            tokens.clear();
            for (std::string t; s >> t;) tokens.push_back(t);
            if (!tokens.empty()) return true;
        }
        return false;
    };
    if (!next()) throw std::runtime_error(path + ": empty file");
    std::size_t first = 0;
    if (tokens[0] == "OFF") {
        if (tokens.size() == 1 && !next()) throw std::runtime_error(path + ": no counts");
        first = tokens[0] == "OFF" ? 1 : 0;
    }
    if (tokens.size() < first + 2) throw std::runtime_error(path + ": expected vertex and face counts");
    const unsigned long nv = std::stoul(tokens[first]), nf = std::stoul(tokens[first + 1]);
    Mesh m;
    m.vertices.reserve(nv);
    for (unsigned long v = 0; v < nv; ++v) {
        if (!next() || tokens.size() < 3) throw std::runtime_error(path + ": vertex " + std::to_string(v) + " missing");
        float p[3];
        for (int k = 0; k < 3; ++k) {
            double value = 0.0;  // read as double, then rounded to float
            std::from_chars(tokens[k].data(), tokens[k].data() + tokens[k].size(), value);
            p[k] = float(value);
        }
        m.vertices.push_back({p[0], p[1], p[2]});
    }
    for (unsigned long f = 0; f < nf; ++f) {
        if (!next()) throw std::runtime_error(path + ": face " + std::to_string(f) + " missing");
        const unsigned long n = std::stoul(tokens[0]);
        if (tokens.size() < n + 1) throw std::runtime_error(path + ": face " + std::to_string(f) + " is short");
        std::vector<std::uint32_t> c;
        for (unsigned long k = 1; k <= n; ++k) {
            const unsigned long i = std::stoul(tokens[k]);
            if (i >= nv) throw std::runtime_error(path + ": face " + std::to_string(f) + " has a bad index");
            c.push_back(std::uint32_t(i));
        }
        for (std::size_t k = 2; k < c.size(); ++k) m.indices.insert(m.indices.end(), {c[0], c[k - 1], c[k]});
    }
    if (m.indices.empty()) throw std::runtime_error(path + ": no triangles");
    for (std::uint32_t i : m.indices) m.bounds.add(m.vertices[i]);
    return m;
}

// ---- the camera: a pinhole; pixel (0, 0) is the top left ----
struct Camera {
    V3 eye, at, up{0, 1, 0};
    float fovy = 60.0f;
    V3 forward, right, upv;

    void make_basis() {
        forward = normalize(at - eye);
        V3 r = cross(forward, up);
        if (!(length(r) > 1e-6f * length(up))) {
            const std::array<V3, 3> axes{V3{0, 1, 0}, V3{0, 0, 1}, V3{1, 0, 0}};
            V3 best = axes[0];
            for (const V3& a : axes)
                if (std::fabs(dot(a, forward)) < std::fabs(dot(best, forward))) best = a;
            r = cross(forward, best);
        }
        right = normalize(r);
        upv = cross(right, forward);
    }
    V3 direction(int px, int py, int width, int height) const {
        const float tan_half = std::tan(fovy * (std::numbers::pi_v<float> / 360.0f));
        const float aspect = float(width) / float(height);
        const float sx = (2.0f * (float(px) + 0.5f) / float(width) - 1.0f) * tan_half * aspect;
        const float sy = (1.0f - 2.0f * (float(py) + 0.5f) / float(height)) * tan_half;
        return normalize(forward + right * sx + upv * sy);
    }
};

// The bench's default for a mesh file: a 3/4 view from the front-right and above, just far enough
// back that the whole box is in view with a 5% margin.
Camera frame(const Bounds& b) {
    Camera c;
    c.at = b.center();
    float radius = 0.5f * b.diagonal();
    if (!(radius > 0.0f)) radius = 1.0f;
    const V3 direction = normalize(V3{0.6f, 0.45f, 0.8f});
    Camera axes;
    axes.eye = direction;
    axes.at = {0, 0, 0};
    axes.make_basis();
    const float tan_half = std::tan(c.fovy * (std::numbers::pi_v<float> / 360.0f)) / 1.05f;
    float distance = 1.05f * radius;
    for (int k = 0; k < 8; ++k) {
        const V3 corner{(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z};
        const V3 offset = corner - c.at;
        const float sideways = std::max(std::fabs(dot(offset, axes.right)), std::fabs(dot(offset, axes.upv)));
        distance = std::max(distance, sideways / tan_half - dot(offset, axes.forward));
    }
    const float magnitude = std::max({std::fabs(c.at.x), std::fabs(c.at.y), std::fabs(c.at.z)});
    distance = std::max(distance, 1e-4f * magnitude);
    c.eye = c.at + direction * distance;
    return c;
}

std::vector<float> numbers(const std::string& text, std::size_t count, const char* what) {
    std::vector<float> v;
    std::stringstream s(text);
    for (std::string item; std::getline(s, item, ',');) v.push_back(std::stof(item));
    if (v.size() != count)
        throw std::runtime_error(std::string(what) + ": expected " + std::to_string(count) + " numbers");
    return v;
}

// ---- rays in Embree's layouts ----
struct Ray {
    V3 org, dir;
    float tfar;
    bool active;
    std::uint32_t pixel;
};

// The rays of a width x height image in 4x4 pixel packets, packet by packet (row-major packets),
// lane = x % 4 + 4 (y % 4); lanes outside the image are inactive.
std::vector<Ray> camera_rays(const Camera& c, int width, int height) {
    const int bx = (width + 3) / 4, by = (height + 3) / 4;
    std::vector<Ray> rays(std::size_t(bx) * std::size_t(by) * 16);
    for (int ty = 0; ty < by; ++ty)
        for (int tx = 0; tx < bx; ++tx)
            for (int lane = 0; lane < 16; ++lane) {
                const int x = tx * 4 + lane % 4, y = ty * 4 + lane / 4;
                Ray& r = rays[(std::size_t(ty) * std::size_t(bx) + std::size_t(tx)) * 16 + std::size_t(lane)];
                r.active = x < width && y < height;
                r.org = c.eye;
                r.dir = c.direction(std::min(x, width - 1), std::min(y, height - 1), width, height);
                r.tfar = std::numeric_limits<float>::infinity();
                r.pixel = r.active ? std::uint32_t(y) * std::uint32_t(width) + std::uint32_t(x) : 0;
            }
    return rays;
}

void set_ray(RTCRay& r, const Ray& in) {
    r.org_x = in.org.x;
    r.org_y = in.org.y;
    r.org_z = in.org.z;
    r.dir_x = in.dir.x;
    r.dir_y = in.dir.y;
    r.dir_z = in.dir.z;
    r.tnear = 0.0f;
    r.tfar = in.tfar;
    r.time = 0.0f;
    r.mask = 0xFFFFFFFFu;
    r.id = 0;
    r.flags = 0;
}
template <class R16>
void set_lane(R16& r, int i, const Ray& in) {
    r.org_x[i] = in.org.x;
    r.org_y[i] = in.org.y;
    r.org_z[i] = in.org.z;
    r.dir_x[i] = in.dir.x;
    r.dir_y[i] = in.dir.y;
    r.dir_z[i] = in.dir.z;
    r.tnear[i] = 0.0f;
    r.tfar[i] = in.tfar;
    r.time[i] = 0.0f;
    r.mask[i] = 0xFFFFFFFFu;
    r.id[i] = unsigned(i);
    r.flags[i] = 0;
}

struct alignas(64) Valid16 {
    int lane[16];
};

// The answers of one query kind on one layout: per ray slot, the hit triangle (closest) or 1/0 (occlusion).
using Answers = std::vector<std::uint32_t>;
constexpr std::uint32_t kMiss = 0xFFFFFFFFu;

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

struct Timing {
    std::string layout, flag;
    double mrays = 0.0;
};

// Times rtcIntersect16 / rtcOccluded16 on the packets with an active ray, rtcIntersect1 /
// rtcOccluded1 per active ray and rtcIntersect1M / rtcOccluded1M over the active rays.
class Tracer {
public:
    Tracer(RTCScene scene, const std::vector<Ray>& rays, bool closest) : scene_(scene), rays_(rays), closest_(closest) {
        for (std::size_t p = 0; p < rays.size() / 16; ++p) {
            Valid16 v{};
            bool any = false;
            for (int i = 0; i < 16; ++i) any |= (v.lane[i] = rays[p * 16 + std::size_t(i)].active ? -1 : 0) != 0;
            if (!any) continue;
            packets_.push_back(p);
            valid_.push_back(v);
        }
        for (std::size_t k = 0; k < rays.size(); ++k)
            if (rays[k].active) active_.push_back(k);
        if (closest_) {
            hit16_.resize(packets_.size());
            hit1_.resize(active_.size());
        } else {
            ray16_.resize(packets_.size());
            ray1_.resize(active_.size());
        }
    }
    std::size_t count() const { return active_.size(); }

    // The best Mrays/s of each layout and flag; answers of the packet16 coherent pass.
    std::vector<Timing> time(int repeats, Answers& answers) {
        std::vector<Timing> out;
        for (const char* layout : {"packet16", "single", "stream"})
            for (RTCIntersectContextFlags flag :
                 {RTC_INTERSECT_CONTEXT_FLAG_COHERENT, RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT}) {
                double best = 1e300;
                for (int r = 0; r < repeats; ++r) {
                    fill(layout);  // untimed
                    RTCIntersectContext context;
                    rtcInitIntersectContext(&context);
                    context.flags = flag;
                    const auto start = std::chrono::steady_clock::now();
                    trace(layout, context);
                    best = std::min(best, seconds_since(start));
                }
                out.push_back({layout, flag == RTC_INTERSECT_CONTEXT_FLAG_COHERENT ? "coherent" : "incoherent",
                               double(count()) / best / 1e6});
                if (std::string(layout) == "packet16" && flag == RTC_INTERSECT_CONTEXT_FLAG_COHERENT)
                    answers = read16();
            }
        return out;
    }

private:
    void fill(const std::string& layout) {
        if (layout == "packet16") {
            for (std::size_t k = 0; k < packets_.size(); ++k)
                for (int i = 0; i < 16; ++i) {
                    const Ray& r = rays_[packets_[k] * 16 + std::size_t(i)];
                    if (closest_) {
                        set_lane(hit16_[k].ray, i, r);
                        hit16_[k].hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
                        hit16_[k].hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
                    } else {
                        set_lane(ray16_[k], i, r);
                    }
                }
            return;
        }
        for (std::size_t k = 0; k < active_.size(); ++k) {
            if (closest_) {
                set_ray(hit1_[k].ray, rays_[active_[k]]);
                hit1_[k].hit.geomID = hit1_[k].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            } else {
                set_ray(ray1_[k], rays_[active_[k]]);
            }
        }
    }
    void trace(const std::string& layout, RTCIntersectContext& context) {
        if (layout == "packet16") {
            for (std::size_t k = 0; k < packets_.size(); ++k)
                closest_ ? rtcIntersect16(valid_[k].lane, scene_, &context, &hit16_[k])
                         : rtcOccluded16(valid_[k].lane, scene_, &context, &ray16_[k]);
        } else if (layout == "single") {
            for (std::size_t k = 0; k < active_.size(); ++k)
                closest_ ? rtcIntersect1(scene_, &context, &hit1_[k]) : rtcOccluded1(scene_, &context, &ray1_[k]);
        } else {
            closest_ ? rtcIntersect1M(scene_, &context, hit1_.data(), unsigned(hit1_.size()), sizeof(RTCRayHit))
                     : rtcOccluded1M(scene_, &context, ray1_.data(), unsigned(ray1_.size()), sizeof(RTCRay));
        }
    }
    Answers read16() const {
        Answers a(rays_.size(), closest_ ? kMiss : 0u);
        for (std::size_t k = 0; k < packets_.size(); ++k)
            for (int i = 0; i < 16; ++i) {
                if (!valid_[k].lane[i]) continue;
                const std::size_t slot = packets_[k] * 16 + std::size_t(i);
                if (closest_)
                    a[slot] = hit16_[k].hit.geomID[i] == RTC_INVALID_GEOMETRY_ID ? kMiss : hit16_[k].hit.primID[i];
                else
                    a[slot] = ray16_[k].tfar[i] == -std::numeric_limits<float>::infinity() ? 1u : 0u;
            }
        return a;
    }

public:
    // Where each packet sits among the traced ones (packets with no active ray are not traced).
    std::vector<std::size_t> packet_index() const {
        std::vector<std::size_t> index(rays_.size() / 16, std::size_t(-1));
        for (std::size_t k = 0; k < packets_.size(); ++k) index[packets_[k]] = k;
        return index;
    }
    const RTCRayHit16& hit16(std::size_t k) const { return hit16_[k]; }

private:
    RTCScene scene_;
    const std::vector<Ray>& rays_;
    bool closest_;
    std::vector<std::size_t> packets_, active_;
    std::vector<Valid16> valid_;
    std::vector<RTCRayHit16> hit16_;
    std::vector<RTCRay16> ray16_;
    std::vector<RTCRayHit> hit1_;
    std::vector<RTCRay> ray1_;
};

struct Options {
    std::string scene, camera, light, json, dump;
    int width = 1024, height = 1024, repeats = 5;
    bool robust = true;
};

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
            return argv[++i];
        };
        if (a == "--scene")
            o.scene = value();
        else if (a == "--camera")
            o.camera = value();
        else if (a == "--light")
            o.light = value();
        else if (a == "--width")
            o.width = std::stoi(value());
        else if (a == "--height")
            o.height = std::stoi(value());
        else if (a == "--repeats")
            o.repeats = std::stoi(value());
        else if (a == "--json")
            o.json = value();
        else if (a == "--dump")
            o.dump = value();
        else if (a == "--non-robust")
            o.robust = false;
        else if (a == "--help" || a == "-h") {
            std::printf(
                "usage: embree-direct --scene FILE.off [--camera EX,EY,EZ,AX,AY,AZ,FOVY] [--light X,Y,Z]\n"
                "       [--width 1024] [--height 1024] [--repeats 5] [--non-robust] [--json FILE] [--dump PREFIX]\n");
            std::exit(0);
        } else {
            throw std::runtime_error("unknown option '" + a + "' (--help lists them)");
        }
    }
    if (o.scene.empty()) throw std::runtime_error("--scene FILE.off is required");
    if (o.width < 1 || o.height < 1 || o.width > 65536 || o.height > 65536) throw std::runtime_error("bad image size");
    if (o.repeats < 1) throw std::runtime_error("--repeats must be at least 1");
    return o;
}

template <class T>
void write_file(const std::string& path, const std::vector<T>& data) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size() * sizeof(T)));
    if (!out) throw std::runtime_error("cannot write '" + path + "'");
}

int run(int argc, char** argv) {
    const Options o = parse(argc, argv);
    const Mesh mesh = load_off(o.scene);

    Camera camera;
    if (o.camera.empty()) {
        camera = frame(mesh.bounds);
    } else {
        const std::vector<float> v = numbers(o.camera, 7, "--camera");
        camera.eye = {v[0], v[1], v[2]};
        camera.at = {v[3], v[4], v[5]};
        camera.fovy = v[6];
    }
    camera.make_basis();
    V3 light = (camera.eye + mesh.bounds.center()) * 0.5f;
    if (!o.light.empty()) {
        const std::vector<float> v = numbers(o.light, 3, "--light");
        light = {v[0], v[1], v[2]};
    }

    RTCDevice device = rtcNewDevice("verbose=0");
    if (!device) throw std::runtime_error("cannot create an Embree device");
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, o.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), mesh.vertices.size()));
    auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(std::uint32_t), mesh.indices.size() / 3));
    if (!vb || !ib) throw std::runtime_error("Embree could not allocate the geometry buffers");
    std::memcpy(vb, mesh.vertices.data(), mesh.vertices.size() * sizeof(V3));
    std::memcpy(ib, mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t));
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene);
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE) throw std::runtime_error("Embree failed to build the scene");

    // Primary rays.
    const std::vector<Ray> primary = camera_rays(camera, o.width, o.height);
    Tracer primary_tracer(scene, primary, true);
    Answers primary_hits;
    const std::vector<Timing> primary_times = primary_tracer.time(o.repeats, primary_hits);

    // Shadow rays from the hits (the bench's make_shadow_rays): the hit point lifted off the surface
    // by 1e-4 of the scene's diagonal, towards the light, ending just before it.
    const float offset = 1e-4f * mesh.bounds.diagonal();
    std::vector<Ray> shadow(primary.size());
    const std::vector<std::size_t> index = primary_tracer.packet_index();
    for (std::size_t slot = 0; slot < primary.size(); ++slot) {
        shadow[slot] = Ray{{0, 0, 0}, {0, 0, 1}, 0.0f, false, primary[slot].pixel};
        if (!primary[slot].active || primary_hits[slot] == kMiss) continue;
        const RTCRayHit16& h = primary_tracer.hit16(index[slot / 16]);
        const int i = int(slot % 16);
        const float u = h.hit.u[i], v = h.hit.v[i];
        const std::uint32_t* c = &mesh.indices[3 * std::size_t(primary_hits[slot])];
        const V3 v0 = mesh.vertices[c[0]], v1 = mesh.vertices[c[1]], v2 = mesh.vertices[c[2]];
        const V3 position = v0 * (1.0f - u - v) + v1 * u + v2 * v;
        V3 n = cross(v1 - v0, v2 - v0);
        if (dot(n, primary[slot].dir) > 0.0f) n = n * -1.0f;
        n = normalize(n);
        const V3 lift = n * (dot(n, light - position) >= 0.0f ? offset : -offset);
        Ray& r = shadow[slot];
        r.org = position + lift;
        r.dir = light - r.org;
        if (!(dot(r.dir, r.dir) > 0.0f)) continue;
        r.tfar = 1.0f - 1e-4f;
        r.active = true;
    }
    Tracer shadow_tracer(scene, shadow, false);
    Answers shadow_blocked;
    const std::vector<Timing> shadow_times = shadow_tracer.time(o.repeats, shadow_blocked);

    std::size_t hits = 0, blocked = 0;
    for (std::size_t slot = 0; slot < primary.size(); ++slot) {
        hits += primary[slot].active && primary_hits[slot] != kMiss;
        blocked += shadow[slot].active && shadow_blocked[slot] != 0;
    }

    std::printf("embree-direct: %s, %zu triangles, %dx%d, %s scene, 1 thread, best of %d\n", o.scene.c_str(),
                mesh.indices.size() / 3, o.width, o.height, o.robust ? "robust" : "non-robust", o.repeats);
    std::printf("camera %g,%g,%g,%g,%g,%g,%g  light %g,%g,%g\n", camera.eye.x, camera.eye.y, camera.eye.z, camera.at.x,
                camera.at.y, camera.at.z, camera.fovy, light.x, light.y, light.z);
    std::printf("%-8s %-9s %-11s %10s %8s\n", "mode", "layout", "flag", "Mrays/s", "rays");
    for (const Timing& t : primary_times)
        std::printf("%-8s %-9s %-11s %10.3f %8zu\n", "primary", t.layout.c_str(), t.flag.c_str(), t.mrays,
                    primary_tracer.count());
    for (const Timing& t : shadow_times)
        std::printf("%-8s %-9s %-11s %10.3f %8zu\n", "shadow", t.layout.c_str(), t.flag.c_str(), t.mrays,
                    shadow_tracer.count());
    std::printf("primary hits %zu, shadow rays blocked %zu\n", hits, blocked);

    if (!o.json.empty()) {
        std::ofstream out(o.json);
        out << "{\n  \"scene\": \"" << o.scene << "\", \"width\": " << o.width << ", \"height\": " << o.height
            << ", \"robust\": " << (o.robust ? "true" : "false") << ",\n  \"primary_hits\": " << hits
            << ", \"shadow_blocked\": " << blocked << ",\n  \"timings\": [\n";
        bool first = true;
        for (const auto* list : {&primary_times, &shadow_times})
            for (const Timing& t : *list) {
                out << (first ? "" : ",\n") << "    {\"mode\": \"" << (list == &primary_times ? "primary" : "shadow")
                    << "\", \"layout\": \"" << t.layout << "\", \"flag\": \"" << t.flag
                    << "\", \"mrays_per_s\": " << t.mrays << "}";
                first = false;
            }
        out << "\n  ]\n}\n";
        if (!out) throw std::runtime_error("cannot write '" + o.json + "'");
    }
    if (!o.dump.empty()) {
        std::vector<std::uint32_t> hit_image(std::size_t(o.width) * std::size_t(o.height), kMiss);
        std::vector<std::uint8_t> shadow_image(hit_image.size(), 0);
        for (std::size_t slot = 0; slot < primary.size(); ++slot) {
            if (!primary[slot].active) continue;
            hit_image[primary[slot].pixel] = primary_hits[slot];
            shadow_image[primary[slot].pixel] = shadow[slot].active && shadow_blocked[slot] != 0;
        }
        write_file(o.dump + ".primary", hit_image);
        write_file(o.dump + ".shadow", shadow_image);
    }
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "embree-direct: %s\n", e.what());
        return 2;
    }
}
