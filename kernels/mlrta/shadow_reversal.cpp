// Shadow packets traced from their light (MLRTA section 6): the packet form of reversed(), with a
// common origin, in SSE (the library's baseline), four lanes at a time; and the policy Mlrta's
// occlusion queries apply.
#include "mlrta/shadow_reversal.hpp"

#include <cmath>

#include "simd/sse_lanes.hpp"

namespace beamtrace::mlrta {

namespace {

// How far (in double) the reversed ray's far end lies from the original segment's start: the
// rounding of the new origin org + tfar * dir. Infinite or NaN when the ray cannot be reversed
// (tfar infinite).
double reversal_error(const Ray& ray, const Ray& back) {
    double e2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double start = double(ray.org[k]) + double(ray.dir[k]) * double(ray.tnear);
        const double end = double(back.org[k]) + double(back.dir[k]) * double(back.tfar);
        e2 += (end - start) * (end - start);
    }
    return std::sqrt(e2);
}

}  // namespace

double reversal_tolerance(const Box& b) {
    const Float3 e = b.extent();
    return 1e-6 * std::sqrt(double(e.x) * e.x + double(e.y) * e.y + double(e.z) * e.z);
}

bool reverse_for_occlusion(const Packet16& in, double tolerance, Packet16& out) {
    out = in;
    const std::uint32_t active = in.active & 0xFFFFu;
    if (active == 0) return false;
    // Rays that already share one origin (traced from their light by the caller) stay as they are.
    const int lead = __builtin_ctz(active);
    bool one_origin = true;
    for (std::uint32_t m = active; m && one_origin; m &= m - 1) {
        const int i = __builtin_ctz(m);
        one_origin = in.org_x[i] == in.org_x[lead] && in.org_y[i] == in.org_y[lead] && in.org_z[i] == in.org_z[lead];
    }
    if (one_origin) return false;
    if (reverse_towards_light(in, float(tolerance), out)) return true;
    for (std::uint32_t m = in.active & 0xFFFFu; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        const Ray ray = in.ray(i), back = reversed(ray);
        if (!(reversal_error(ray, back) <= tolerance)) {
            out = in;
            return false;
        }
        out.set_ray(i, back);
    }
    return true;
}

bool reverse_towards_light(const Packet16& packet, float tolerance, Packet16& out) {
    using B = sse::Floats;
    constexpr int W = int(B::size);
    const std::uint32_t active = packet.active & 0xFFFFu;
    if (active == 0) return false;
    // 2^-23, twice a float's relative rounding. Per component: the aim's distance from the light plus
    // its rounding (2^-24 (|org| + |dir|)), and the rounding of the new far end light + (start -
    // light) and of start (2^-24 (|start - light| + |start| + |dir tnear|)); doubled. Twice the
    // largest component bounds a Euclidean length: every end stays within the tolerance.
    const B rounding(1.0f / 8388608.0f), two(2.0f), one(1.0f), limit(tolerance);
    const int lead = __builtin_ctz(active);
    const float* org[3] = {packet.org_x, packet.org_y, packet.org_z};
    const float* dir[3] = {packet.dir_x, packet.dir_y, packet.dir_z};
    const B light[3] = {B(org[0][lead] + dir[0][lead]), B(org[1][lead] + dir[1][lead]), B(org[2][lead] + dir[2][lead])};
    std::uint32_t fine = 0;
    B start[3][16 / W];
    for (int base = 0; base < 16; base += W) {
        const B tnear = B::load_unaligned(packet.tnear + base), tfar = B::load_unaligned(packet.tfar + base);
        auto ok = (tnear < one) & (tfar <= one) & (tnear <= tfar);
        for (int k = 0; k < 3; ++k) {
            const B o = B::load_unaligned(org[k] + base), d = B::load_unaligned(dir[k] + base);
            const B s = o + d * tnear;
            start[k][base / W] = s;
            const B miss = xsimd::abs((o + d) - light[k]) + (xsimd::abs(o) + xsimd::abs(d)) * rounding;
            const B end = (xsimd::abs(s - light[k]) + xsimd::abs(s) + xsimd::abs(d * tnear)) * rounding;
            ok = ok & (two * miss <= limit) & (two * end <= limit);
        }
        fine |= sse::bits_of(ok) << base;
    }
    if ((fine & active) != active) return false;
    float* back_org[3] = {out.org_x, out.org_y, out.org_z};
    float* back_dir[3] = {out.dir_x, out.dir_y, out.dir_z};
    for (int base = 0; base < 16; base += W) {
        const sse::Mask on = sse::lanes_on(active >> base);
        const B tnear = B::load_unaligned(packet.tnear + base), tfar = B::load_unaligned(packet.tfar + base);
        for (int k = 0; k < 3; ++k) {
            xsimd::select(on, light[k], B::load_unaligned(org[k] + base)).store_unaligned(back_org[k] + base);
            xsimd::select(on, start[k][base / W] - light[k], B::load_unaligned(dir[k] + base))
                .store_unaligned(back_dir[k] + base);
        }
        xsimd::select(on, (one - tfar) / (one - tnear), tnear).store_unaligned(out.tnear + base);
        xsimd::select(on, one, tfar).store_unaligned(out.tfar + base);
    }
    out.active = packet.active;
    return true;
}

}  // namespace beamtrace::mlrta
