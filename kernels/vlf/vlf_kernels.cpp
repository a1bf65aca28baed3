// Run-time choice of the VLF-RT kernels, and the scalar footprint scan (the reference; the
// reference of the entry occlusion is in entry_occlusion.hpp).
#include "vlf/vlf_kernels.hpp"

#include "vlf/tile_footprint.hpp"

namespace beamtrace::vlf {
namespace {

std::uint32_t scan_scalar(const std::uint32_t* footprints, std::uint32_t count, std::uint32_t ray,
                          std::uint32_t* passing) {
    std::uint32_t n = 0;
    for (std::uint32_t k = 0; k < count; ++k)
        if (footprints_meet(footprints[k], ray)) passing[n++] = k;
    return n;
}

constexpr VlfKernels kScalar{Isa::scalar, nullptr, scan_scalar, occlude_entries_scalar, nullptr,
                             batch_candidates_scalar, batch_test_scalar};
constexpr VlfKernels kSse42{Isa::sse42, simd_sse42::lookup_packet, simd_sse42::scan_footprints, occlude_entries_scalar,
                            nullptr, batch_candidates_scalar, batch_test_scalar};
constexpr VlfKernels kAvx2{Isa::avx2, simd_avx2::lookup_packet, simd_avx2::scan_footprints, occlude_entries_scalar,
                           nullptr, batch_candidates_scalar, batch_test_scalar};
constexpr VlfKernels kAvx512{Isa::avx512, simd_avx512::lookup_packet, simd_avx512::scan_footprints,
                             simd_avx512::occlude_entries, simd_avx512::closest_entries,
                             simd_avx512::batch_candidates, simd_avx512::batch_test};

}  // namespace

const VlfKernels& vlf_kernels(Isa isa) {
    switch (isa) {
        case Isa::scalar: return kScalar;
        case Isa::sse42: return kSse42;
        case Isa::avx2: return kAvx2;
        case Isa::avx512: return kAvx512;
    }
    return kScalar;
}

}  // namespace beamtrace::vlf
