// The scalar table of the VLF-RT kernels: the footprint scan's reference here, the others' in
// entry_occlusion.hpp and tile_ray_batch.hpp.
#include "vlf/vlf_kernels.hpp"

#include "vlf/query/tile_footprint.hpp"

namespace beamtrace::vlf {
namespace {

std::uint32_t scan_scalar(const std::uint32_t* footprints, std::uint32_t count, std::uint32_t ray,
                          std::uint32_t* passing) {
    std::uint32_t n = 0;
    for (std::uint32_t k = 0; k < count; ++k)
        if (footprints_meet(footprints[k], ray)) passing[n++] = k;
    return n;
}

}  // namespace

const VlfKernels& vlf_kernels(Isa isa) { return simd::select<VlfKernels>(isa); }

}  // namespace beamtrace::vlf

template <>
const beamtrace::vlf::VlfKernels& beamtrace::simd::table<beamtrace::vlf::VlfKernels, beamtrace::Isa::scalar>() {
    using namespace beamtrace::vlf;
    static constexpr VlfKernels kScalar{Isa::scalar,       nullptr,
                                        scan_scalar,       occlude_entries_scalar,
                                        nullptr,           batch_candidates_scalar,
                                        batch_test_scalar, store_tile_rays_scalar};
    return kScalar;
}
