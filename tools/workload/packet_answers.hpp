#pragma once
// A packet's answers into the per-slot arrays of a RaySet (slots p * 16 .. p * 16 + 15), which the
// caller has cleared: the hits of its active lanes, the occlusion bits that are set.
#include <cstdint>

#include "beamtrace/ray.hpp"

namespace beamtrace::workload {

inline void spread_hits(const Packet16& packet, const PacketHits16& out, Hit* slots) {
    for (std::uint32_t m = packet.active & 0xFFFFu; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        slots[i] = out.hit(i);
    }
}

inline void spread_bits(std::uint32_t bits, std::uint8_t* slots) {
    for (std::uint32_t m = bits & 0xFFFFu; m; m &= m - 1) slots[__builtin_ctz(m)] = 1;
}

}  // namespace beamtrace::workload
