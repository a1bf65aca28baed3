#pragma once
// The SIMD kernels of VLF-RT, one table per instruction set (simd/dispatch.hpp): the packet lookup (packet_lookup.hpp),
// the footprint scan (tile_footprint.hpp) and the occlusion by a run of tile entries (entry_occlusion.hpp; AVX-512
// only, the reference elsewhere) and the closest hit among a leaf's entries (entry_closest_hit.hpp; AVX-512 only,
// nullptr elsewhere: the walk's own leaf loop), and the two kernels of batched one-tile occlusion (tile_ray_batch.hpp;
// AVX-512 and AVX2, the references on SSE4.2) and their records' stores (tile_ray_store.hpp).
#include <cstdint>

#include "simd/dispatch.hpp"
#include "simd/isa.hpp"
#include "vlf/query/entry_closest_hit.hpp"
#include "vlf/query/entry_occlusion.hpp"
#include "vlf/stream/packet_lookup.hpp"
#include "vlf/stream/tile_ray_batch.hpp"
#include "vlf/stream/tile_ray_store.hpp"

namespace beamtrace::vlf {

// Indices k < count of the entries whose footprint meets the ray's, ascending, into passing
// (room for count + 16: SIMD stores may write past the last index); returns how many.
using ScanFootprintsFn = std::uint32_t (*)(const std::uint32_t* footprints, std::uint32_t count, std::uint32_t ray,
                                           std::uint32_t* passing);

struct VlfKernels {
    Isa isa;
    LookupPacketFn lookup_packet;  // nullptr for Isa::scalar: packets run the single-ray set-up lane by lane
    ScanFootprintsFn scan_footprints;
    OccludeEntriesFn occlude_entries;
    ClosestEntriesFn closest_entries;
    BatchCandidatesFn batch_candidates;  // tile_ray_batch.hpp (AVX-512, AVX2; the references on SSE4.2)
    BatchTestFn batch_test;
    StoreTileRaysFn store_tile_rays;  // tile_ray_store.hpp (AVX-512; the reference elsewhere)
};

// The kernels of one instruction set (which must be available: throws beamtrace::Error otherwise).
const VlfKernels& vlf_kernels(Isa isa);

}  // namespace beamtrace::vlf

BEAMTRACE_KERNEL_TABLE(beamtrace::vlf::VlfKernels);
