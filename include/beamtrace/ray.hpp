#pragma once
// Rays, 4x4 ray packets and hits.
#include <cstdint>
#include <limits>

#include "beamtrace/vec.hpp"

namespace beamtrace {

// Triangle id of "no hit".
inline constexpr std::uint32_t kNoHit = 0xFFFFFFFFu;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

// One ray: points org + t * dir for tnear <= t <= tfar. dir need not be normalised (t is measured in
// units of |dir|); tnear may be negative (the segment then reaches behind org); tfar may be +infinity.
//
// A ray describes a segment when org and dir are finite, dir is not the zero vector, tnear is finite,
// tfar is not NaN and tnear <= tfar. Every query of every engine reports no hit (and no occlusion) for
// any other ray -- a NaN or infinite component, a zero direction, tnear > tfar -- and treats it in a
// packet as an inactive lane, leaving the other rays' answers unchanged. Never an error, a crash or
// a hang.
//
// Rounding: a hit within rounding of tnear or tfar (a ray starting exactly on a surface) may be
// reported or not. Answers are exact (as exact geometry, watertight) while the products of the
// coordinates involved stay inside float's range: docs/robustness.md gives the range and what
// happens beyond it.
struct Ray {
    Float3 org;
    float tnear = 0.0f;
    Float3 dir;
    float tfar = kInfinity;
};

// The same segment traced from its far end: origin org + tfar * dir, direction -dir, interval
// [0, tfar - tnear] (the origin is rounded once). Shadow rays that end at a point light become rays
// with a common origin.
Ray reversed(const Ray& ray);

// Closest hit. Barycentrics: the hit point is (1-u-v)*v0 + u*v1 + v*v2 (the usual convention of
// production ray tracers, so hits compare directly with the oracle's in tests).
struct Hit {
    float t = kInfinity;
    std::uint32_t triangle = kNoHit;
    float u = 0.0f;
    float v = 0.0f;

    bool hit() const { return triangle != kNoHit; }
};

// 16 rays as a 4x4 tile (ray i = row * 4 + column), structure of arrays, 64-byte aligned: one
// AVX-512 register, two AVX2 or four SSE registers per component. Rays whose bit is clear in
// `active` are ignored by every query and report no hit.
struct alignas(64) Packet16 {
    static constexpr int kSize = 16;
    float org_x[16], org_y[16], org_z[16];
    float dir_x[16], dir_y[16], dir_z[16];
    float tnear[16], tfar[16];
    std::uint32_t active = 0;  // bit i set: ray i takes part

    Ray ray(int i) const {
        return Ray{{org_x[i], org_y[i], org_z[i]}, tnear[i], {dir_x[i], dir_y[i], dir_z[i]}, tfar[i]};
    }
    void set_ray(int i, const Ray& r) {
        org_x[i] = r.org.x;
        org_y[i] = r.org.y;
        org_z[i] = r.org.z;
        dir_x[i] = r.dir.x;
        dir_y[i] = r.dir.y;
        dir_z[i] = r.dir.z;
        tnear[i] = r.tnear;
        tfar[i] = r.tfar;
    }
};

// Closest hits of a Packet16, structure of arrays.
struct alignas(64) PacketHits16 {
    float t[16];
    std::uint32_t triangle[16];
    float u[16], v[16];

    Hit hit(int i) const { return Hit{t[i], triangle[i], u[i], v[i]}; }
    void set_hit(int i, const Hit& h) {
        t[i] = h.t;
        triangle[i] = h.triangle;
        u[i] = h.u;
        v[i] = h.v;
    }
};

}  // namespace beamtrace
