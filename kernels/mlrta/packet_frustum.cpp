// Run-time choice of the packet frustum culling kernel, and the scalar one (the reference).
#include "mlrta/packet_frustum.hpp"

#include <algorithm>
#include <string>

#include "beamtrace/error.hpp"

namespace beamtrace::mlrta {

namespace {

std::uint32_t scalar_misses(const PacketFrustum& f, const Triangle* tris, int n) {
    std::uint32_t bits = 0;
    for (int i = 0; i < n; ++i)
        if (f.misses(tris[i])) bits |= 1u << i;
    return bits;
}

}  // namespace

PacketFrustum make_packet_frustum(const Packet16& packet, std::uint32_t mask) {
    PacketFrustum f;
    if (mask == 0) return f;
    const float* org[3] = {packet.org_x, packet.org_y, packet.org_z};
    const float* dir[3] = {packet.dir_x, packet.dir_y, packet.dir_z};
    const int first = __builtin_ctz(mask);
    for (std::uint32_t b = mask; b; b &= b - 1)
        for (int k = 0; k < 3; ++k)
            if (!(org[k][__builtin_ctz(b)] == org[k][first])) return f;  // several origins: no frustum
    const float a0 = std::fabs(dir[0][first]), a1 = std::fabs(dir[1][first]), a2 = std::fabs(dir[2][first]);
    f.m = a0 >= a1 ? (a0 >= a2 ? 0 : 2) : (a1 >= a2 ? 1 : 2);
    f.j0 = f.m == 0 ? 1 : 0;
    f.j1 = f.m == 2 ? 1 : 2;
    f.sm = std::signbit(dir[f.m][first]) ? -1.0f : 1.0f;
    f.origin = Float3{org[0][first], org[1][first], org[2][first]};
    for (int j = 0; j < 3; ++j) f.slope[j] = {kInfinity, -kInfinity};
    float reach = 0.0f;
    for (std::uint32_t b = mask; b; b &= b - 1) {
        const int i = __builtin_ctz(b);
        const float dm = std::fabs(dir[f.m][i]);
        reach = std::max(reach, packet.tfar[i] * dm);
        for (int j = 0; j < 3; ++j) {
            const float q = dir[j][i] / dm;
            f.slope[j] = {std::min(f.slope[j].lo, q), std::max(f.slope[j].hi, q)};
        }
    }
    // Slopes of rays and corners both carry rounding: widen generously (relative and absolute).
    for (int j = 0; j < 3; ++j) {
        const float spread = (f.slope[j].hi - f.slope[j].lo) + std::fabs(f.slope[j].lo) + std::fabs(f.slope[j].hi);
        f.slope[j] = {f.slope[j].lo - spread * 1e-4f - 1e-6f, f.slope[j].hi + spread * 1e-4f + 1e-6f};
    }
    f.reach = reach * (1.0f + 1.0f / 65536.0f);  // the product's rounding, generously
    f.valid = std::isfinite(f.slope[f.j0].lo) && std::isfinite(f.slope[f.j0].hi) && std::isfinite(f.slope[f.j1].lo) &&
              std::isfinite(f.slope[f.j1].hi);
    return f;
}

FrustumCullKernel frustum_cull_kernel(Isa isa) {
    if (!isa_available(isa)) throw Error(std::string("instruction set ") + isa_name(isa) + " is not available");
    switch (isa) {
        case Isa::scalar: return scalar_misses;
        case Isa::sse42: return frustum_cull_sse42::misses;
        case Isa::avx2: return frustum_cull_avx2::misses;
        case Isa::avx512: return frustum_cull_avx512::misses;
    }
    return scalar_misses;
}

}  // namespace beamtrace::mlrta
