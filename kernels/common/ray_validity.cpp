#include "common/ray_validity.hpp"

#include <xsimd/xsimd.hpp>

namespace beamtrace {

std::uint32_t segment_lanes(const Packet16& p) {
    using B = xsimd::batch<float, xsimd::sse4_2>;
    constexpr int W = int(B::size);
    std::uint32_t lanes = 0;
    for (int i = 0; i < 16; i += W) {
        const B ox = B::load_unaligned(p.org_x + i), oy = B::load_unaligned(p.org_y + i),
                oz = B::load_unaligned(p.org_z + i);
        const B dx = B::load_unaligned(p.dir_x + i), dy = B::load_unaligned(p.dir_y + i),
                dz = B::load_unaligned(p.dir_z + i);
        const B tnear = B::load_unaligned(p.tnear + i), tfar = B::load_unaligned(p.tfar + i);
        // The same sum, in the same order, as describes_segment.
        const B finite = ((ox - ox) + (oy - oy)) + ((oz - oz) + (dx - dx)) + ((dy - dy) + (dz - dz)) + (tnear - tnear);
        const B zero(0.0f);
        const auto moves = (dx != zero) | (dy != zero) | (dz != zero);
        const auto ok = (finite == zero) & moves & (tnear <= tfar);
        lanes |= std::uint32_t(_mm_movemask_ps(ok)) << i;
    }
    return lanes;
}

}  // namespace beamtrace
