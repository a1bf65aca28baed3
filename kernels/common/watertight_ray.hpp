#pragma once
// Per-ray set-up of the watertight ray/triangle test (Woop, Benthin, Wald: "Watertight Ray/Triangle
// Intersection", JCGT 2013): the dominant direction axis kz, the two others kx, ky (swapped when
// dir[kz] < 0 to keep the winding) and the shear that maps the ray onto +z.
#include <bit>
#include <cmath>
#include <cstdint>

#include "beamtrace/ray.hpp"

namespace beamtrace {

struct WatertightRay {
    Float3 org;
    int kx = 0, ky = 1, kz = 2;
    float sx = 0, sy = 0, sz = 1;
    float tnear = 0, tfar = kInfinity;
};

inline WatertightRay make_watertight_ray(const Ray& ray) {
    WatertightRay w;
    w.org = ray.org;
    const float ax = std::fabs(ray.dir.x), ay = std::fabs(ray.dir.y), az = std::fabs(ray.dir.z);
    w.kz = (ax > ay) ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
    w.kx = w.kz == 2 ? 0 : w.kz + 1;
    w.ky = w.kx == 2 ? 0 : w.kx + 1;
    if (ray.dir[w.kz] < 0.0f) {
        const int k = w.kx;
        w.kx = w.ky;
        w.ky = k;
    }
    w.sx = ray.dir[w.kx] / ray.dir[w.kz];
    w.sy = ray.dir[w.ky] / ray.dir[w.kz];
    w.sz = 1.0f / ray.dir[w.kz];
    w.tnear = ray.tnear;
    w.tfar = ray.tfar;
    return w;
}

// The same set-up for the 16 rays of a packet, structure of arrays. The axis choices are stored as
// floats (0, 1, 2) so that SIMD kernels select components with float compares.
struct alignas(64) WatertightPacket16 {
    float org_x[16], org_y[16], org_z[16];
    float kx[16], ky[16], kz[16];
    float sx[16], sy[16], sz[16];
    float tnear[16], tfar[16];
    std::uint32_t active = 0;
    // Shared by every active lane (set by make_watertight_packet): kernels then permute the corners
    // once per triangle instead of per lane. The arithmetic, and so every result, is the same.
    bool same_axes = false;    // one (kx, ky, kz) for all, in axis[]
    bool same_origin = false;  // one origin for all, lane `first`'s
    int axis[3] = {0, 1, 2};
    int first = 0;
};

// The set-up of every lane as make_watertight_ray does it (the reference of the SIMD forms: the
// scalar table's set-up, kdtree/packet/packet_setup_kernels.hpp).
inline WatertightPacket16 make_watertight_packet_reference(const Packet16& p) {
    WatertightPacket16 w;
    for (int i = 0; i < 16; ++i) {
        Ray r = p.ray(i);
        if (((p.active >> i) & 1u) == 0) r.dir = Float3{0, 0, 1};  // inactive lanes: harmless values
        const WatertightRay s = make_watertight_ray(r);
        w.org_x[i] = s.org.x;
        w.org_y[i] = s.org.y;
        w.org_z[i] = s.org.z;
        w.kx[i] = float(s.kx);
        w.ky[i] = float(s.ky);
        w.kz[i] = float(s.kz);
        w.sx[i] = s.sx;
        w.sy[i] = s.sy;
        w.sz[i] = s.sz;
        w.tnear[i] = s.tnear;
        w.tfar[i] = s.tfar;
    }
    w.active = p.active & 0xFFFFu;
    if (w.active != 0) {
        const int f = __builtin_ctz(w.active);
        w.first = f;
        w.axis[0] = int(w.kx[f]);
        w.axis[1] = int(w.ky[f]);
        w.axis[2] = int(w.kz[f]);
        w.same_axes = w.same_origin = true;
        for (std::uint32_t b = w.active; b; b &= b - 1) {
            const int i = __builtin_ctz(b);
            w.same_axes = w.same_axes && w.kx[i] == w.kx[f] && w.ky[i] == w.ky[f] && w.kz[i] == w.kz[f];
            // Bit patterns, not values: 0 and -0 give differently signed differences.
            w.same_origin = w.same_origin &&
                            std::bit_cast<std::uint32_t>(w.org_x[i]) == std::bit_cast<std::uint32_t>(w.org_x[f]) &&
                            std::bit_cast<std::uint32_t>(w.org_y[i]) == std::bit_cast<std::uint32_t>(w.org_y[f]) &&
                            std::bit_cast<std::uint32_t>(w.org_z[i]) == std::bit_cast<std::uint32_t>(w.org_z[f]);
        }
    }
    return w;
}

// The same, bit for bit, four lanes at a time (the SSE4.2 form of watertight_packet_impl.hpp).
WatertightPacket16 make_watertight_packet(const Packet16& p);
// The same, written into w (every field; no copy of the 768-byte result).
void make_watertight_packet(const Packet16& p, WatertightPacket16& w);

}  // namespace beamtrace
