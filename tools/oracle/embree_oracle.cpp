// The Embree 3 oracle (see embree_oracle.hpp for the ray semantics it implements).
#include "oracle/embree_oracle.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/error.hpp"
#include "oracle/embree_device.hpp"
#include "oracle/embree_ray_fill.hpp"

namespace beamtrace::oracle {

static_assert(sizeof(Float3) == 3 * sizeof(float), "Float3 must be three packed floats");

struct EmbreeOracle::Impl {
    // Declared first: destroyed last, after the scene it made.
    std::unique_ptr<EmbreeDevice> device;
    RTCScene scene = nullptr;
    // Embree primID -> scene triangle id; empty when they are equal (no degenerate triangles).
    std::vector<std::uint32_t> prim_to_triangle;
    std::size_t embree_triangles = 0;
    double build_seconds = 0.0;
    std::size_t memory_bytes = 0;
    bool robust = true;
    EmbreeSceneOptions options;

    Impl() = default;
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;
    ~Impl() {
        if (scene != nullptr) rtcReleaseScene(scene);
    }

    std::uint32_t triangle_id(unsigned prim) const { return prim_to_triangle.empty() ? prim : prim_to_triangle[prim]; }
    void check(const char* step) { device->check(step); }
};

EmbreeOracle::EmbreeOracle(const Scene& scene, const EmbreeSceneOptions& options) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    const auto start = std::chrono::steady_clock::now();

    m.device = std::make_unique<EmbreeDevice>("embree oracle", options.build_threads);
    m.scene = rtcNewScene(m.device->get());
    m.check("rtcNewScene");
    m.robust = options.robust;
    m.options = options;
    rtcSetSceneFlags(m.scene, options.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);
    m.check("scene set-up");

    // Only triangles of non-zero area go to Embree.
    const std::size_t n = scene.triangle_count();
    const std::size_t kept = n - scene.degenerate_count();
    if (kept != n) {
        m.prim_to_triangle.reserve(kept);
        for (std::uint32_t t = 0; t < n; ++t)
            if (!scene.is_degenerate(t)) m.prim_to_triangle.push_back(t);
    }
    m.embree_triangles = kept;

    if (kept > 0) {
        RTCGeometry geometry = rtcNewGeometry(m.device->get(), RTC_GEOMETRY_TYPE_TRIANGLE);
        m.check("rtcNewGeometry");
        rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);

        const auto vertices = scene.vertices();
        // rtcSetNewGeometryBuffer allocates (and pads) Embree's own copy.
        auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               sizeof(Float3), vertices.size()));
        auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), kept));
        if (vb == nullptr || ib == nullptr) {
            rtcReleaseGeometry(geometry);
            m.check("rtcSetNewGeometryBuffer");
            throw Error("embree oracle: rtcSetNewGeometryBuffer returned no buffer");
        }
        std::memcpy(vb, vertices.data(), vertices.size() * sizeof(Float3));
        const auto indices = scene.indices();
        if (m.prim_to_triangle.empty()) {
            std::memcpy(ib, indices.data(), indices.size() * sizeof(std::uint32_t));
        } else {
            for (std::size_t p = 0; p < kept; ++p)
                std::memcpy(ib + 3 * p, indices.data() + 3 * std::size_t{m.prim_to_triangle[p]},
                            3 * sizeof(std::uint32_t));
        }
        rtcCommitGeometry(geometry);
        rtcAttachGeometryByID(m.scene, geometry, 0);
        rtcReleaseGeometry(geometry);  // the scene holds it now
        m.check("geometry set-up");
    }

    rtcCommitScene(m.scene);
    m.check("rtcCommitScene");

    m.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    m.memory_bytes = m.device->bytes();
}

EmbreeOracle::~EmbreeOracle() = default;
EmbreeOracle::EmbreeOracle(EmbreeOracle&&) noexcept = default;
EmbreeOracle& EmbreeOracle::operator=(EmbreeOracle&&) noexcept = default;

Hit EmbreeOracle::intersect1(const Ray& ray) const {
    const auto s = to_embree(ray);
    if (!s) return Hit{};
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    fill_ray(rh.ray, *s);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return Hit{};
    return Hit{s->caller_t(rh.ray.tfar), impl_->triangle_id(rh.hit.primID), rh.hit.u, rh.hit.v};
}

bool EmbreeOracle::occluded1(const Ray& ray) const {
    const auto s = to_embree(ray);
    if (!s) return false;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    fill_ray(r, *s);
    rtcOccluded1(impl_->scene, &context, &r);
    return r.tfar == -kInfinity;  // Embree marks an occluded ray with tfar = -inf
}

void EmbreeOracle::intersect16(const Packet16& packet, PacketHits16& hits) const {
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[16];
    EmbreeSegment lane[16];
    for (int i = 0; i < 16; ++i) {
        std::optional<EmbreeSegment> s;
        if ((packet.active >> i) & 1u) s = to_embree(packet.ray(i));
        valid[i] = s ? -1 : 0;
        lane[i] = s ? *s : EmbreeSegment{};
        fill_lane(rh.ray, i, s ? *s : kIdleLane);
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect16(valid, impl_->scene, &context, &rh);
    for (int i = 0; i < 16; ++i) {
        if (valid[i] == 0 || rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) {
            hits.set_hit(i, Hit{});
        } else {
            hits.set_hit(i, Hit{lane[i].caller_t(rh.ray.tfar[i]), impl_->triangle_id(rh.hit.primID[i]), rh.hit.u[i],
                                rh.hit.v[i]});
        }
    }
}

std::uint32_t EmbreeOracle::occluded16(const Packet16& packet) const {
    alignas(64) RTCRay16 r;
    alignas(64) int valid[16];
    for (int i = 0; i < 16; ++i) {
        std::optional<EmbreeSegment> s;
        if ((packet.active >> i) & 1u) s = to_embree(packet.ray(i));
        valid[i] = s ? -1 : 0;
        fill_lane(r, i, s ? *s : kIdleLane);
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded16(valid, impl_->scene, &context, &r);
    std::uint32_t mask = 0;
    for (int i = 0; i < 16; ++i)
        if (valid[i] != 0 && r.tfar[i] == -kInfinity) mask |= 1u << i;
    return mask;
}

double EmbreeOracle::build_seconds() const { return impl_->build_seconds; }
std::size_t EmbreeOracle::memory_bytes() const { return impl_->memory_bytes; }
std::size_t EmbreeOracle::embree_triangle_count() const { return impl_->embree_triangles; }
bool EmbreeOracle::robust() const { return impl_->robust; }
const EmbreeSceneOptions& EmbreeOracle::options() const { return impl_->options; }
RTCSceneTy* EmbreeOracle::native_scene() const { return impl_->scene; }
std::uint32_t EmbreeOracle::triangle_id(unsigned embree_prim) const { return impl_->triangle_id(embree_prim); }
std::uint32_t EmbreeOracle::triangle_id(unsigned /*geometry*/, unsigned embree_prim) const {
    return impl_->triangle_id(embree_prim);
}

}  // namespace beamtrace::oracle
