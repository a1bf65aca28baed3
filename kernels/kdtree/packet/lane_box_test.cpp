// The per-lane slab test: set-up and scalar reference.
#include "kdtree/packet/lane_box_test.hpp"

#include "simd/sse_lanes.hpp"

namespace beamtrace::kdtree {

LaneBoxRays make_lane_box_rays(const Packet16& packet, float pad) {
    LaneBoxRays s;
    make_lane_box_rays(packet, pad, s);
    return s;
}

void make_lane_box_rays(const Packet16& packet, float pad, LaneBoxRays& s) {
    // Four lanes at a time (SSE, the library's baseline): copies and reciprocals, each lane's the
    // same division as one at a time.
    using B = sse::Floats;
    const float* org[3] = {packet.org_x, packet.org_y, packet.org_z};
    const float* dir[3] = {packet.dir_x, packet.dir_y, packet.dir_z};
    for (int base = 0; base < 16; base += int(B::size)) {
        for (int k = 0; k < 3; ++k) {
            B::load_unaligned(org[k] + base).store_aligned(s.org[k] + base);
            (B(1.0f) / B::load_unaligned(dir[k] + base)).store_aligned(s.inv[k] + base);
        }
        B::load_unaligned(packet.tnear + base).store_aligned(s.tnear + base);
    }
    s.pad = pad;
}

std::uint32_t lanes_meeting_box(const LaneBoxRays& s, const float* tfar, std::uint32_t lanes, const Box& box) {
    std::uint32_t out = 0;
    for (std::uint32_t b = lanes; b; b &= b - 1) {
        const int i = __builtin_ctz(b);
        if (s.meets(i, tfar[i], box)) out |= 1u << i;
    }
    return out;
}

}  // namespace beamtrace::kdtree
