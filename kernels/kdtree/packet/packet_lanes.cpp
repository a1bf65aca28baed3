#include "kdtree/packet/packet_lanes.hpp"

#include <cfloat>

#include "common/ray_validity.hpp"
#include "simd/sse_lanes.hpp"

namespace beamtrace::kdtree {

namespace {

using B = sse::Floats;
using Mask = sse::Mask;
using sse::bits_of;
using sse::lanes_on;
constexpr int W = int(B::size);

using sse::max_as_std;  // std::min / std::max lane by lane, and across the lanes
using sse::min_as_std;
using sse::least;
using sse::most;

}  // namespace

PacketLanes packet_lanes(const Packet16& p) {
    PacketLanes l;
    packet_lanes(p, l);
    return l;
}

void packet_lanes(const Packet16& p, PacketLanes& l) {
    l.flat = 0;
    for (std::uint32_t& n : l.negative) n = 0;
    l.valid = p.active & 0xFFFFu & segment_lanes(p);
    const B tiny(FLT_MIN);
    for (int base = 0; base < 16; base += W) {
        const B dx = B::load_unaligned(p.dir_x + base), dy = B::load_unaligned(p.dir_y + base),
                dz = B::load_unaligned(p.dir_z + base);
        const B speed = xsimd::sqrt(dx * dx + dy * dy + dz * dz), inv = B(1.0f) / speed;
        speed.store_aligned(l.speed + base);
        (dx * inv).store_aligned(l.unit[0] + base);
        (dy * inv).store_aligned(l.unit[1] + base);
        (dz * inv).store_aligned(l.unit[2] + base);
        // Not >= FLT_MIN (NaN included): no usable reciprocal.
        const Mask usable = (xsimd::abs(dx) >= tiny) & (xsimd::abs(dy) >= tiny) & (xsimd::abs(dz) >= tiny);
        l.flat |= (~bits_of(usable) & 0xFu) << base;
        l.negative[0] |= std::uint32_t(_mm_movemask_ps(dx)) << base;
        l.negative[1] |= std::uint32_t(_mm_movemask_ps(dy)) << base;
        l.negative[2] |= std::uint32_t(_mm_movemask_ps(dz)) << base;
    }
    l.flat &= l.valid;
}

Interval lane_range(const float* v, std::uint32_t lanes) {
    B lo(kInfinity), hi(-kInfinity);
    for (int base = 0; base < 16; base += W) {
        if (((lanes >> base) & 0xFu) == 0) continue;
        const Mask on = lanes_on(lanes >> base);
        const B x = B::load_unaligned(v + base);
        lo = min_as_std(lo, xsimd::select(on, x, B(kInfinity)));
        hi = max_as_std(hi, xsimd::select(on, x, B(-kInfinity)));
    }
    return {least(lo), most(hi)};
}

GroupRanges group_ranges(const Packet16& p, const PacketLanes& l, std::uint32_t lanes) {
    const float* org[3] = {p.org_x, p.org_y, p.org_z};
    B lo[6], hi[6];
    for (int k = 0; k < 6; ++k) {
        lo[k] = B(kInfinity);
        hi[k] = B(-kInfinity);
    }
    for (int base = 0; base < 16; base += W) {
        if (((lanes >> base) & 0xFu) == 0) continue;
        const Mask on = lanes_on(lanes >> base);
        for (int k = 0; k < 6; ++k) {
            const B x = k < 3 ? B::load_unaligned(org[k] + base) : B::load_aligned(l.unit[k - 3] + base);
            lo[k] = min_as_std(lo[k], xsimd::select(on, x, B(kInfinity)));
            hi[k] = max_as_std(hi[k], xsimd::select(on, x, B(-kInfinity)));
        }
    }
    GroupRanges g;
    for (int k = 0; k < 3; ++k) {
        g.org[k] = {least(lo[k]), most(hi[k])};
        g.unit[k] = {least(lo[k + 3]), most(hi[k + 3])};
    }
    return g;
}

float farthest_distance(const float* tfar, const float* speed, std::uint32_t lanes) {
    B far(-kInfinity);
    for (int base = 0; base < 16; base += W) {
        if (((lanes >> base) & 0xFu) == 0) continue;
        const B d = B::load_unaligned(tfar + base) * B::load_unaligned(speed + base);
        far = max_as_std(far, xsimd::select(lanes_on(lanes >> base), d, B(-kInfinity)));
    }
    return most(far);
}

CellEntry enter_cell(const Packet16& p, std::uint32_t lanes, const float* speed, const Box& box, float pad) {
    const float* org[3] = {p.org_x, p.org_y, p.org_z};
    const float* dir[3] = {p.dir_x, p.dir_y, p.dir_z};
    const B rel(kRelativePad), pad_b(pad);
    B c0(kInfinity), c1(-kInfinity), near(kInfinity);
    B org_lo[3], org_hi[3], inv_lo[3], inv_hi[3];
    for (int k = 0; k < 3; ++k) {
        org_lo[k] = inv_lo[k] = B(kInfinity);
        org_hi[k] = inv_hi[k] = B(-kInfinity);
    }
    std::uint32_t kept = 0;
    for (int base = 0; base < 16; base += W) {
        if (((lanes >> base) & 0xFu) == 0) continue;
        const Mask on = lanes_on(lanes >> base);
        const bool all_on = ((lanes >> base) & 0xFu) == 0xFu;
        const B s = B::load_aligned(speed + base);
        const B tnear = B::load_unaligned(p.tnear + base) * s;
        B enter = tnear, exit = B::load_unaligned(p.tfar + base) * s;
        for (int k = 0; k < 3; ++k) {
            const B o = B::load_unaligned(org[k] + base);
            const B inv = s / B::load_unaligned(dir[k] + base);  // reciprocal of the unit direction's component
            const B a = (B(box.lower[k]) - o) * inv, b = (B(box.upper[k]) - o) * inv;
            const auto swap = a > b;
            enter = max_as_std(enter, xsimd::select(swap, b, a));
            exit = min_as_std(exit, xsimd::select(swap, a, b));
            if (all_on) {  // the same values without the selects
                org_lo[k] = min_as_std(org_lo[k], o);
                org_hi[k] = max_as_std(org_hi[k], o);
                inv_lo[k] = min_as_std(inv_lo[k], inv);
                inv_hi[k] = max_as_std(inv_hi[k], inv);
            } else {
                org_lo[k] = min_as_std(org_lo[k], xsimd::select(on, o, B(kInfinity)));
                org_hi[k] = max_as_std(org_hi[k], xsimd::select(on, o, B(-kInfinity)));
                inv_lo[k] = min_as_std(inv_lo[k], xsimd::select(on, inv, B(kInfinity)));
                inv_hi[k] = max_as_std(inv_hi[k], xsimd::select(on, inv, B(-kInfinity)));
            }
        }
        // Rounding of enter / exit is covered by widening the packet's interval afterwards.
        const B slack = (xsimd::abs(enter) + xsimd::abs(exit)) * rel + pad_b;
        const Mask in = on & !(enter > exit + slack);
        kept |= bits_of(in) << base;
        c0 = min_as_std(c0, xsimd::select(in, enter, B(kInfinity)));
        c1 = max_as_std(c1, xsimd::select(in, exit, B(-kInfinity)));
        near = min_as_std(near, xsimd::select(in, tnear, B(kInfinity)));
    }
    CellEntry e;
    e.lanes = kept;
    e.c0 = least(c0);
    e.c1 = most(c1);
    e.near = least(near);
    for (int k = 0; k < 3; ++k) {
        e.org[k] = {least(org_lo[k]), most(org_hi[k])};
        e.inv[k] = {least(inv_lo[k]), most(inv_hi[k])};
    }
    return e;
}

}  // namespace beamtrace::kdtree
