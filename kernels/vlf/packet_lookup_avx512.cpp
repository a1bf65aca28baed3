// The packet lookup for avx512 (this unit alone is compiled for it).
// GCC 12 reports its own AVX-512 intrinsics (the _mm512_undefined_* operands of masked
// conversions, min and max) as reading uninitialised values; they are not.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include "vlf/packet_lookup_impl.hpp"

namespace beamtrace::vlf::lookup_avx512 {
void lookup_packet(const LookupTables& t, const Packet16& p, PacketLookup& out) {
    lookup_packet_simd<xsimd::avx512bw>(t, p, out);
}
}  // namespace beamtrace::vlf::lookup_avx512
#pragma GCC diagnostic pop
