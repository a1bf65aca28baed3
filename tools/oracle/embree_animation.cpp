#include "oracle/embree_animation.hpp"

#include <embree3/rtcore.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include "beamtrace/error.hpp"
#include "oracle/embree_device.hpp"
#include "report/wall_clock.hpp"

namespace beamtrace::oracle {

namespace {

using report::seconds_since;

}  // namespace

struct EmbreeAnimation::Impl {
    std::unique_ptr<EmbreeDevice> device;  // declared first: destroyed after the scene
    RTCScene scene = nullptr;
    AnimatedScene animation;
    EmbreeMotion motion;
    std::vector<std::uint32_t> static_ids, moving_ids;  // Embree primID -> triangle id, per geometry
    std::vector<std::uint32_t> moving_vertices;         // the moving geometry's vertices (scene ids)
    RTCGeometry moving = nullptr;                       // geometry 1 (owned by the scene)
    float* moving_buffer = nullptr;                     // its vertex buffer (dynamic kinds)
    double build_seconds = 0.0;

    Impl(const AnimatedScene& a, EmbreeMotion m) : animation(a), motion(m) {}
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;
    ~Impl() {
        if (scene != nullptr) rtcReleaseScene(scene);
    }

    // A triangle geometry of the given triangles, vertices renumbered by index_of (empty: kept).
    RTCGeometry new_geometry(std::span<const std::uint32_t> triangles, std::span<const std::uint32_t> index_of,
                             unsigned time_steps) {
        RTCGeometry g = rtcNewGeometry(device->get(), RTC_GEOMETRY_TYPE_TRIANGLE);
        device->check("rtcNewGeometry");
        if (time_steps > 1) rtcSetGeometryTimeStepCount(g, time_steps);
        auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                       3 * sizeof(std::uint32_t), triangles.size()));
        if (ib == nullptr) {
            rtcReleaseGeometry(g);
            device->check("rtcSetNewGeometryBuffer");
            throw Error("embree animation: rtcSetNewGeometryBuffer returned no index buffer");
        }
        const auto indices = animation.indices();
        for (std::size_t p = 0; p < triangles.size(); ++p)
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t v = indices[3 * std::size_t(triangles[p]) + std::size_t(c)];
                ib[3 * p + std::size_t(c)] = index_of.empty() ? v : index_of[v];
            }
        return g;
    }

    float* new_vertex_buffer(RTCGeometry g, unsigned slot, std::size_t count) {
        auto* vb = static_cast<float*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, slot, RTC_FORMAT_FLOAT3, sizeof(Float3), count));
        if (vb == nullptr) {
            device->check("rtcSetNewGeometryBuffer");
            throw Error("embree animation: rtcSetNewGeometryBuffer returned no vertex buffer");
        }
        return vb;
    }

    void write_moving(float t) {
        for (std::size_t i = 0; i < moving_vertices.size(); ++i) {
            const Float3 p = animation.position(moving_vertices[i], t);
            std::memcpy(moving_buffer + 3 * i, &p, sizeof p);
        }
    }
};

EmbreeAnimation::EmbreeAnimation(const AnimatedScene& scene, EmbreeMotion motion, int build_threads)
    : impl_(std::make_unique<Impl>(scene, motion)) {
    Impl& m = *impl_;
    const auto start = std::chrono::steady_clock::now();
    const std::size_t keyframes = scene.keyframe_count();
    if (motion == EmbreeMotion::motion_blur) {
        const auto times = scene.times();
        for (std::size_t k = 0; k < keyframes; ++k)
            if (std::fabs(times[k] - float(double(k) / double(keyframes - 1))) > 1e-6f)
                throw Error("embree animation: motion blur needs keyframes at uniform times over [0, 1]; keyframe " +
                            std::to_string(k) + " is at " + std::to_string(times[k]));
    }
    m.device = std::make_unique<EmbreeDevice>("embree animation", build_threads);
    m.scene = rtcNewScene(m.device->get());
    m.device->check("rtcNewScene");
    const bool dynamic = motion != EmbreeMotion::motion_blur;
    rtcSetSceneFlags(m.scene, dynamic ? RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_DYNAMIC)
                                      : RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(m.scene, dynamic ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_HIGH);
    m.device->check("scene set-up");

    const Scene& still = scene.static_part();
    for (std::uint32_t t = 0; t < scene.triangle_count(); ++t) {
        if (scene.is_moving(t))
            m.moving_ids.push_back(t);
        else if (!still.is_degenerate(t))
            m.static_ids.push_back(t);
    }

    // Geometry 0: what does not move (the first keyframe's vertices), high quality, built once.
    // Geometry 1: what moves. Empty geometries are left out (their ids stay reserved).
    if (!m.static_ids.empty()) {
        RTCGeometry g = m.new_geometry(m.static_ids, {}, 1);
        const auto first = scene.keyframe(0);
        std::memcpy(m.new_vertex_buffer(g, 0, first.size()), first.data(), first.size() * sizeof(Float3));
        rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(m.scene, g, 0);
        rtcReleaseGeometry(g);
        m.device->check("static geometry");
    }
    if (!m.moving_ids.empty()) {
        std::vector<std::uint32_t> index_of(scene.vertex_count(), 0xFFFFFFFFu);
        const auto indices = scene.indices();
        for (std::uint32_t t : m.moving_ids)
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t v = indices[3 * std::size_t(t) + std::size_t(c)];
                if (index_of[v] == 0xFFFFFFFFu) {
                    index_of[v] = std::uint32_t(m.moving_vertices.size());
                    m.moving_vertices.push_back(v);
                }
            }
        const auto steps = dynamic ? 1u : unsigned(keyframes);
        RTCGeometry g = m.new_geometry(m.moving_ids, index_of, steps);
        if (dynamic) {
            m.moving_buffer = m.new_vertex_buffer(g, 0, m.moving_vertices.size());
            m.write_moving(scene.start_time());
            rtcSetGeometryBuildQuality(
                g, motion == EmbreeMotion::dynamic_refit ? RTC_BUILD_QUALITY_REFIT : RTC_BUILD_QUALITY_LOW);
        } else {
            for (unsigned k = 0; k < steps; ++k) {
                float* vb = m.new_vertex_buffer(g, k, m.moving_vertices.size());
                const auto frame = scene.keyframe(k);
                for (std::size_t i = 0; i < m.moving_vertices.size(); ++i)
                    std::memcpy(vb + 3 * i, &frame[m.moving_vertices[i]], sizeof(Float3));
            }
            rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_MEDIUM);
        }
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(m.scene, g, 1);
        m.moving = g;
        rtcReleaseGeometry(g);  // the scene holds it
        m.device->check("moving geometry");
    }
    rtcCommitScene(m.scene);
    m.device->check("rtcCommitScene");
    m.build_seconds = seconds_since(start);
}

EmbreeAnimation::~EmbreeAnimation() = default;

double EmbreeAnimation::set_time(float t) {
    Impl& m = *impl_;
    if (m.motion == EmbreeMotion::motion_blur || m.moving == nullptr) return 0.0;
    if (!std::isfinite(t)) throw Error("embree animation: set_time needs a finite time");
    const auto start = std::chrono::steady_clock::now();
    m.write_moving(t);
    rtcUpdateGeometryBuffer(m.moving, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(m.moving);
    rtcCommitScene(m.scene);
    m.device->check("set_time");
    return seconds_since(start);
}

double EmbreeAnimation::build_seconds() const { return impl_->build_seconds; }
std::size_t EmbreeAnimation::memory_bytes() const { return impl_->device->bytes(); }
RTCSceneTy* EmbreeAnimation::native_scene() const { return impl_->scene; }

std::uint32_t EmbreeAnimation::triangle_id(unsigned geometry, unsigned primitive) const {
    return geometry == 0 ? impl_->static_ids[primitive] : impl_->moving_ids[primitive];
}

}  // namespace beamtrace::oracle
