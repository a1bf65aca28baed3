// The per-lane slab test: set-up, scalar reference and run-time choice of its kernel.
#include "mlrta/lane_slabs.hpp"

#include <string>

#include "beamtrace/error.hpp"

namespace beamtrace::mlrta {

LaneSlabs make_lane_slabs(const Packet16& packet, float pad) {
    LaneSlabs s;
    const float* org[3] = {packet.org_x, packet.org_y, packet.org_z};
    const float* dir[3] = {packet.dir_x, packet.dir_y, packet.dir_z};
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 16; ++i) {
            s.org[k][i] = org[k][i];
            s.inv[k][i] = 1.0f / dir[k][i];
        }
    for (int i = 0; i < 16; ++i) s.tnear[i] = packet.tnear[i];
    s.pad = pad;
    return s;
}

std::uint32_t lanes_meeting_box(const LaneSlabs& s, const float* tfar, std::uint32_t lanes, const Box& box) {
    std::uint32_t out = 0;
    for (std::uint32_t b = lanes; b; b &= b - 1) {
        const int i = __builtin_ctz(b);
        if (s.meets(i, tfar[i], box)) out |= 1u << i;
    }
    return out;
}

LaneBoxKernel lane_box_kernel(Isa isa) {
    if (!isa_available(isa)) throw Error(std::string("instruction set ") + isa_name(isa) + " is not available");
    switch (isa) {
        case Isa::scalar: return lanes_meeting_box;
        case Isa::sse42: return lane_slabs_sse42::meeting;
        case Isa::avx2: return lane_slabs_avx2::meeting;
        case Isa::avx512: return lane_slabs_avx512::meeting;
    }
    return lanes_meeting_box;
}

}  // namespace beamtrace::mlrta
