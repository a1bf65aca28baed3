// make_watertight_packet at the library's baseline: the kernel the per-ISA units use
// (watertight_packet_impl.hpp) four lanes at a time (SSE4.2, the library's minimum).
#include <xsimd/xsimd.hpp>

#include "common/watertight_packet_impl.hpp"
#include "common/watertight_ray.hpp"

namespace beamtrace {

WatertightPacket16 make_watertight_packet(const Packet16& p) {
    WatertightPacket16 w;
    make_watertight_packet(p, w);
    return w;
}

void make_watertight_packet(const Packet16& p, WatertightPacket16& w) {
    simd_impl::make_watertight_packet<xsimd::sse4_2>(p, w);
}

}  // namespace beamtrace
