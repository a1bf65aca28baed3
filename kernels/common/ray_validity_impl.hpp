#pragma once
// describes_segment (ray_validity.hpp) for W lanes at once, written over xsimd's Arch: the scalar
// test's operations lane by lane (x - x is 0 for finite x and NaN otherwise; one sum tests ten
// values), so its lanes agree with describes_segment bit for bit. Included only by the per-ISA units
// (a template of their Arch: no copy compiled for a wider instruction set can reach a narrower unit).
#include <xsimd/xsimd.hpp>

namespace beamtrace::simd {

template <class Arch>
xsimd::batch_bool<float, Arch> describes_segment_lanes(
    const xsimd::batch<float, Arch>& ox, const xsimd::batch<float, Arch>& oy, const xsimd::batch<float, Arch>& oz,
    const xsimd::batch<float, Arch>& dx, const xsimd::batch<float, Arch>& dy, const xsimd::batch<float, Arch>& dz,
    const xsimd::batch<float, Arch>& tnear, const xsimd::batch<float, Arch>& tfar) {
    const xsimd::batch<float, Arch> zero(0.0f);
    const auto finite = ((ox - ox) + (oy - oy)) + ((oz - oz) + (dx - dx)) + ((dy - dy) + (dz - dz)) + (tnear - tnear);
    const auto moves = (dx != zero) | (dy != zero) | (dz != zero);
    return (finite == zero) & moves & (tnear <= tfar);
}

}  // namespace beamtrace::simd
