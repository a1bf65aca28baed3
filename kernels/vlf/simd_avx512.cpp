// The VLF-RT kernels for avx512 (this unit alone is compiled for it).
// GCC 12 reports its own AVX-512 intrinsics (the _mm512_undefined_* operands of masked
// conversions, min and max) as reading uninitialised values; they are not.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include "vlf/entry_closest_hit_impl.hpp"
#include "vlf/entry_occlusion_impl.hpp"
#include "vlf/footprint_scan_impl.hpp"
#include "vlf/packet_lookup_impl.hpp"
#include "vlf/tile_ray_batch_impl.hpp"
#include "vlf/vlf_kernels.hpp"

namespace beamtrace::vlf::simd_avx512 {
void lookup_packet(const LookupTables& t, const Packet16& p, PacketLookup& out, bool first_tiles) {
    lookup_packet_simd<xsimd::avx512bw>(t, p, out, first_tiles);
}
std::uint32_t scan_footprints(const std::uint32_t* footprints, std::uint32_t count, std::uint32_t ray,
                              std::uint32_t* passing) {
    return scan_avx512(footprints, count, ray, passing);
}
EntriesAnswer occlude_entries(const WatertightRay& ray, const Triangle* triangles, const std::uint32_t* footprints,
                              const std::uint32_t* ids, std::uint32_t count, std::uint32_t ray_footprint,
                              bool distinct, std::uint32_t* hit) {
    return occlude_entries_avx512(ray, triangles, footprints, ids, count, ray_footprint, distinct, hit);
}
bool closest_entries(const WatertightRay& ray, const Triangle* triangles, const std::uint32_t* order,
                     const std::uint32_t* footprints, const std::uint32_t* ids, std::uint32_t count,
                     std::uint32_t ray_footprint, TestedIds& tested, Hit& best) {
    return closest_entries_avx512(ray, triangles, order, footprints, ids, count, ray_footprint, tested, best);
}
std::uint32_t batch_candidates(const std::uint32_t* groups, const std::uint32_t* footprints, const std::uint32_t* ids,
                               std::uint32_t first, std::uint32_t count, std::uint32_t ray_footprint, bool distinct,
                               std::uint32_t lane, std::uint32_t* out_ids, std::uint32_t* out_lanes) {
    return batch_candidates_avx512(groups, footprints, ids, first, count, ray_footprint, distinct, lane, out_ids,
                                   out_lanes);
}
std::uint32_t batch_test(const TileRayBatch& rays, const Triangle* triangles, const std::uint32_t* ids,
                         const std::uint32_t* lanes, std::uint32_t count, std::uint32_t occluded) {
    return batch_test_avx512(rays, triangles, ids, lanes, count, occluded);
}
}  // namespace beamtrace::vlf::simd_avx512
#pragma GCC diagnostic pop
