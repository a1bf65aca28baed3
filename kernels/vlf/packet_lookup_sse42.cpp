// The packet lookup for sse42 (this unit alone is compiled for it).
#include "vlf/packet_lookup_impl.hpp"

namespace beamtrace::vlf::lookup_sse42 {
void lookup_packet(const LookupTables& t, const Packet16& p, PacketLookup& out) {
    lookup_packet_simd<xsimd::sse4_2>(t, p, out);
}
}  // namespace beamtrace::vlf::lookup_sse42
