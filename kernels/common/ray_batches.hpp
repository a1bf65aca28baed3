#pragma once
// One ray against a run of triangles with the dispatched watertight kernels, eight at a time
// (ray_x4 for four or fewer): what every single-ray leaf test does.
#include <cstdint>

#include "common/triangle_kernels.hpp"

namespace beamtrace {

// tri(j): the j-th triangle of the run (0 <= j < count). After each batch of n triangles from
// `first`, on_batch(first, n, lanes) (lane k: triangle first + k); it returns false to stop. The ray
// may be changed in between (a nearer tfar once a hit is found).
template <class TriangleAt, class OnBatch>
void test_ray_in_batches(const TriangleKernels& kernels, const WatertightRay& ray, std::uint32_t count,
                         TriangleAt&& tri, OnBatch&& on_batch) {
    for (std::uint32_t first = 0; first < count; first += 8) {
        const int n = int(count - first < 8 ? count - first : 8);
        const Triangle* batch[8];
        for (int k = 0; k < n; ++k) batch[k] = tri(first + std::uint32_t(k));
        LaneHits lanes;
        if (n <= 4)
            kernels.ray_x4(ray, batch, n, lanes);
        else
            kernels.ray_x8(ray, batch, n, lanes);
        if (!on_batch(first, n, lanes)) return;
    }
}

}  // namespace beamtrace
