#pragma once
// One ray against a run of triangles with the dispatched watertight kernels: eight at a time from
// triangles in memory (ray_x4 for four or fewer), or 16 at a time from corner rows (ray_rows): what
// every single-ray leaf test does.
#include <cstddef>
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

// The same for the count triangles from row `first` of nine corner rows (TriangleKernels::ray_rows;
// kdtree::PacketTables stores a tree's leaf triangles so), 16 at a time.
template <class OnBatch>
void test_ray_in_rows(const TriangleKernels& kernels, const WatertightRay& ray, const float* rows, std::size_t stride,
                      std::size_t first_row, std::uint32_t count, OnBatch&& on_batch) {
    for (std::uint32_t first = 0; first < count; first += 16) {
        const int n = int(count - first < 16 ? count - first : 16);
        LaneHits lanes;
        kernels.ray_rows(ray, rows, stride, first_row + first, n, lanes);
        if (!on_batch(first, n, lanes)) return;
    }
}

}  // namespace beamtrace
