#include "kdtree/packet/packet_bounds.hpp"

namespace beamtrace::kdtree {

void BlockBounds::set(int p, const PacketBounds& b, float packet_reach) {
    for (int k = 0; k < 3; ++k) {
        org_lo[k][p] = b.org[k].lo;
        org_hi[k][p] = b.org[k].hi;
        inv_lo[k][p] = b.inv[k].lo;
        inv_hi[k][p] = b.inv[k].hi;
    }
    reach[p] = packet_reach;
}

PacketBounds BlockBounds::bounds(int p) const {
    PacketBounds b;
    for (int k = 0; k < 3; ++k) {
        b.org[k] = {org_lo[k][p], org_hi[k][p]};
        b.inv[k] = {inv_lo[k][p], inv_hi[k][p]};
        b.sign[k] = sign[k];
    }
    b.pad = pad;
    return b;
}

std::uint32_t block_meeting_reference(const BlockBounds& block, const Box& box, float t0) {
    std::uint32_t bits = 0;
    for (int p = 0; p < block.count; ++p)
        if (!packet_misses_box(block.bounds(p), box, t0, block.reach[p])) bits |= 1u << p;
    return bits;
}

}  // namespace beamtrace::kdtree
