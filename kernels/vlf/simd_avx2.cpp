// The VLF-RT kernels for avx2 (this unit alone is compiled for it).
#include "vlf/footprint_scan_impl.hpp"
#include "vlf/packet_lookup_impl.hpp"
#include "vlf/vlf_kernels.hpp"

namespace beamtrace::vlf::simd_avx2 {
void lookup_packet(const LookupTables& t, const Packet16& p, PacketLookup& out, bool first_tiles) {
    lookup_packet_simd<xsimd::avx2>(t, p, out, first_tiles);
}
std::uint32_t scan_footprints(const std::uint32_t* footprints, std::uint32_t count, std::uint32_t ray,
                              std::uint32_t* passing) {
    return scan_avx2(footprints, count, ray, passing);
}
}  // namespace beamtrace::vlf::simd_avx2
