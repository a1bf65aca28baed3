#pragma once
// The lookups of a 4x4 packet at once: 16 rays -> 16 PSF indices, 16 canonical rays cut to the
// bounding sphere. Written once over xsimd batches (packet_lookup_impl.hpp) and compiled per
// instruction set, chosen at run time like the triangle kernels.
#include <cstdint>

#include "beamtrace/ray.hpp"
#include "common/isa.hpp"
#include "vlf/canonical_frame.hpp"
#include "vlf/canonical_ray.hpp"

namespace beamtrace::vlf {

// What the lookups read: the direction table and the frames (structure of arrays).
struct LookupTables {
    // Direction set.
    const float* dir_x = nullptr;
    const float* dir_y = nullptr;
    const float* dir_z = nullptr;
    const std::uint16_t* candidates = nullptr;
    int table = 0, per_cell = 0;
    float half_table = 0.0f;
    // Frame rows of every direction: e1, e2, e3 (x, y, z each), 9 doubles per direction.
    const double* frames = nullptr;
    // Grid.
    double centre_x = 0, centre_y = 0, centre_z = 0, clip_radius = 0;
};

struct alignas(64) PacketLookup {
    std::uint32_t psf[16];
    double ox[16], oy[16], oz[16], dx[16], dy[16], dz[16], t0[16], t1[16];
    std::uint32_t valid = 0;  // bit i: ray i is active, well formed and its segment meets the sphere

    CanonicalRay ray(int i) const { return CanonicalRay{ox[i], oy[i], oz[i], dx[i], dy[i], dz[i], t0[i], t1[i]}; }
};


}  // namespace beamtrace::vlf
