// The one-origin frustum of a packet, and the scalar culling kernel (the reference).
#include "kdtree/packet/one_origin_frustum.hpp"

#include <algorithm>
#include <string>

#include <xsimd/xsimd.hpp>

#include "kdtree/packet/packet_lanes.hpp"

namespace beamtrace::kdtree {

std::uint32_t frustum_misses(const OneOriginFrustum& f, const CornerRows& rows, std::size_t first, int n) {
    std::uint32_t bits = 0;
    for (int i = 0; i < n; ++i)
        if (f.misses(rows.triangle(first + std::size_t(i)))) bits |= 1u << i;
    return bits;
}

void set_frustum_axes(OneOriginFrustum& f, const Packet16& packet, int first) {
    const float* dir[3] = {packet.dir_x, packet.dir_y, packet.dir_z};
    const float a0 = std::fabs(dir[0][first]), a1 = std::fabs(dir[1][first]), a2 = std::fabs(dir[2][first]);
    f.m = a0 >= a1 ? (a0 >= a2 ? 0 : 2) : (a1 >= a2 ? 1 : 2);
    f.j0 = f.m == 0 ? 1 : 0;
    f.j1 = f.m == 2 ? 1 : 2;
    f.sm = std::signbit(dir[f.m][first]) ? -1.0f : 1.0f;
    f.origin = Float3{packet.org_x[first], packet.org_y[first], packet.org_z[first]};
}

void finish_frustum(OneOriginFrustum& f, Interval q0, Interval q1, float reach) {
    // Slopes of rays and corners both carry rounding: widen generously (relative and absolute). In
    // locals, then stored: reading f.slope back as a whole after storing its parts stalled on the
    // stores (a third of this function's time).
    auto widened = [](Interval s) {
        const float spread = (s.hi - s.lo) + std::fabs(s.lo) + std::fabs(s.hi);
        return Interval{s.lo - spread * 1e-4f - 1e-6f, s.hi + spread * 1e-4f + 1e-6f};
    };
    const Interval main = widened({f.sm, f.sm}), s0 = widened(q0), s1 = widened(q1);  // dir_m / |dir_m| on m
    f.slope[f.m] = main;
    f.slope[f.j0] = s0;
    f.slope[f.j1] = s1;
    f.reach = std::max(0.0f, reach) * (1.0f + 1.0f / 65536.0f);  // the product's rounding
    f.valid = std::isfinite(s0.lo) && std::isfinite(s0.hi) && std::isfinite(s1.lo) && std::isfinite(s1.hi);
}

OneOriginFrustum make_one_origin_frustum(const Packet16& packet, std::uint32_t mask) {
    // Lane by lane arithmetic four lanes at a time (SSE), ranges over the group's lanes.
    using B = xsimd::batch<float, xsimd::sse4_2>;
    constexpr int W = int(B::size);
    OneOriginFrustum f;
    if (mask == 0) return f;
    const float* org[3] = {packet.org_x, packet.org_y, packet.org_z};
    const float* dir[3] = {packet.dir_x, packet.dir_y, packet.dir_z};
    const int first = __builtin_ctz(mask);
    std::uint32_t same = 0;
    for (int base = 0; base < 16; base += W) {
        auto eq = B::load_unaligned(org[0] + base) == B(org[0][first]);
        eq = eq & (B::load_unaligned(org[1] + base) == B(org[1][first]));
        eq = eq & (B::load_unaligned(org[2] + base) == B(org[2][first]));
        same |= std::uint32_t(_mm_movemask_ps(eq)) << base;
    }
    if ((same & mask) != mask) return f;  // several origins: no frustum
    set_frustum_axes(f, packet, first);
    alignas(64) float q[2][16], reach[16];
    const int js[2] = {f.j0, f.j1};
    for (int base = 0; base < 16; base += W) {
        const B dm = xsimd::abs(B::load_unaligned(dir[f.m] + base));
        for (int a = 0; a < 2; ++a) (B::load_unaligned(dir[js[a]] + base) / dm).store_aligned(q[a] + base);
        (B::load_unaligned(packet.tfar + base) * dm).store_aligned(reach + base);
    }
    finish_frustum(f, lane_range(q[0], mask), lane_range(q[1], mask), lane_range(reach, mask).hi);
    return f;
}

}  // namespace beamtrace::kdtree
