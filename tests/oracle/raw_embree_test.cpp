// Embree on its own (no oracle in between), for the claims embree_oracle.hpp makes about it: it
// never hits zero-area triangles (the oracle leaves them out anyway) and it misses reversed segments
// (tfar < tnear; the oracle does not even call it for those).
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <vector>

#include "hand_scenes.hpp"

namespace beamtrace {
namespace {

struct RawScene {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    explicit RawScene(const Scene& s);
    ~RawScene() {
        rtcReleaseScene(scene);
        rtcReleaseDevice(device);
    }
    // Closest hit's primID, or -1.
    int intersect(const float o[3], const float d[3], float tnear, float tfar) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh{};
        rh.ray.org_x = o[0];
        rh.ray.org_y = o[1];
        rh.ray.org_z = o[2];
        rh.ray.dir_x = d[0];
        rh.ray.dir_y = d[1];
        rh.ray.dir_z = d[2];
        rh.ray.tnear = tnear;
        rh.ray.tfar = tfar;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &context, &rh);
        return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1 : int(rh.hit.primID);
    }
};

RawScene::RawScene(const Scene& s) {
    device = rtcNewDevice("verbose=0");
    scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), s.vertex_count()));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), s.triangle_count()));
    std::memcpy(vb, s.vertices().data(), s.vertex_count() * sizeof(Float3));
    std::memcpy(ib, s.indices().data(), s.indices().size() * sizeof(std::uint32_t));
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
}

TEST(RawEmbree, SkipsDegenerateTriangles) {
    const RawScene raw(test::with_degenerates());
    ASSERT_EQ(rtcGetDeviceError(raw.device), RTC_ERROR_NONE);

    // Rays through, along and across each degenerate triangle, stopping above the good one.
    struct R {
        float o[3], d[3], tfar;
    };
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<R> rays = {
        {{0.5f, 0.0f, 5.0f}, {0, 0, -1}, 4.5f}, {{-1, 0, 1}, {1, 0, 0}, inf},
        {{0.5f, -1, 1}, {0, 1, 0}, inf},        {{1.5f, -1, 1}, {0, 1, 0}, inf},
        {{0.5f, 0.5f, 5}, {0, 0, -1}, 4.5f},    {{-1, -1, 2}, {1, 1, 0}, inf},
        {{0.25f, 0.25f, 5}, {0, 0, -1}, 4.5f},  {{-1, -1, 4}, {1, 1, 0}, inf},
        {{0.25f, 0.25f, 3}, {1, 0, 0}, inf},    {{0, 0, 5}, {0, 0, -1}, 4.5f},
        {{1, 1, 5}, {0, 0, -1}, 4.5f},
    };
    for (std::size_t i = 0; i < rays.size(); ++i)
        EXPECT_EQ(raw.intersect(rays[i].o, rays[i].d, 0.0f, rays[i].tfar), -1) << i;
    // The good triangle (primID 2) is hit.
    const float o[3] = {0.25f, 0.25f, 10.0f}, d[3] = {0, 0, -1};
    EXPECT_EQ(raw.intersect(o, d, 0.0f, inf), 2);
}

TEST(RawEmbree, MissesReversedSegments) {
    const RawScene raw(test::one_triangle());
    const float o[3] = {0.5f, 0.25f, -2.0f}, d[3] = {0, 0, 1};
    EXPECT_EQ(raw.intersect(o, d, 0.0f, 10.0f), 0);
    EXPECT_EQ(raw.intersect(o, d, 4.0f, 2.0f), -1);  // the hit at t = 3 lies between them
    EXPECT_EQ(raw.intersect(o, d, 3.5f, 2.5f), -1);
    EXPECT_EQ(raw.intersect(o, d, 10.0f, 0.0f), -1);
    EXPECT_EQ(rtcGetDeviceError(raw.device), RTC_ERROR_NONE);
}

}  // namespace
}  // namespace beamtrace
