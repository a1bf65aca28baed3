// Shadow packets traced from their light (MLRTA section 6): the packet form of reversed(), with a
// common origin, in SSE (the library's baseline), four lanes at a time.
#include "beamtrace/mlrta.hpp"
#include "common/sse_lanes.hpp"

namespace beamtrace {

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

}  // namespace beamtrace
