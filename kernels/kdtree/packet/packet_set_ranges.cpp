#include "kdtree/packet/packet_set_ranges.hpp"

#include <algorithm>
#include <cmath>

#include "common/ray_validity.hpp"

namespace beamtrace::kdtree {

namespace {

struct Range {
    float lo = kInfinity, hi = -kInfinity;
    void add(float v) {
        v = v + 0.0f;  // -0 as +0
        lo = std::min(lo, v);  // a NaN v is passed over
        hi = std::max(hi, v);
    }
    Interval interval() const { return {lo, hi}; }
};

}  // namespace

void packet_set_ranges(std::span<const Packet16* const> packets, PacketSetRanges& out) {
    out = PacketSetRanges{};
    Range dir[3], start[3], length, near, far;
    for (const Packet16* packet : packets) {
        const Packet16& p = *packet;
        const float* d[3] = {p.dir_x, p.dir_y, p.dir_z};
        const float* o[3] = {p.org_x, p.org_y, p.org_z};
        for (std::uint32_t m = p.active & 0xFFFFu & segment_lanes(p); m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            if (out.rays == 0) {
                out.main_axis = dominant_axis(d[0][i], d[1][i], d[2][i]);
                out.first_origin = Float3{o[0][i], o[1][i], o[2][i]};
            }
            ++out.rays;
            for (int k = 0; k < 3; ++k) {
                const float v = d[k][i];
                out.zero = out.zero || v == 0.0f;
                out.signs[k] |= std::signbit(v) ? 1u : 2u;
                out.same_origin = out.same_origin && o[k][i] == out.first_origin[k];
                dir[k].add(v);
                start[k].add(o[k][i] + v * p.tnear[i]);
            }
            const float mag = std::fabs(d[out.main_axis][i]);
            length.add((p.tfar[i] - p.tnear[i]) * mag);
            near.add(p.tnear[i] * mag);
            far.add(p.tfar[i] * mag);
        }
    }
    if (out.rays == 0) return;
    for (int k = 0; k < 3; ++k) {
        out.dir[k] = dir[k].interval();
        out.start[k] = start[k].interval();
    }
    out.length = length.interval();
    out.near = near.interval();
    out.far = far.interval();
}

}  // namespace beamtrace::kdtree
