#pragma once
// A ray against its cell's candidates, in the list's order, eight at a time with the dispatched
// watertight kernels, stopping at the first batch that starts beyond what the ray still needs: for a
// closest hit, beyond the closest hit so far; for occlusion, at any hit or beyond the segment's far
// end (seen from the cell's origins). Exact: a candidate is skipped only when its key exceeds the
// limit by a relative margin (docs/raycls.md).
#include <cmath>
#include <cstdint>
#include <span>

#include "beamtrace/query.hpp"
#include "common/triangle_kernels.hpp"
#include "raycls/candidate_list.hpp"

namespace beamtrace::raycls {

// The margin of a key comparison: relative to the magnitudes of the terms that made the key (2^-18,
// a quarter million times coarser than float's rounding, far below any cell).
inline float key_margin(float magnitude) { return magnitude * (1.0f / 262144.0f); }

// The key of the point org + t * dir on a face of sign s and axis k, and the limit a candidate's key
// may reach to be tested (the margin added).
inline float key_stop(float key_origin, float t, float step) {
    if (t == kInfinity) return kInfinity;
    const float along = t * step;
    return key_origin + along + key_margin(std::fabs(key_origin) + std::fabs(along));
}

// The batch of up to eight candidates from `first` against the ray; returns how many were tested.
inline int test_batch(const TriangleKernels& kernels, const WatertightRay& w, std::span<const Candidate> list,
                      std::uint32_t first, LaneHits& lanes) {
    const std::uint32_t n = std::uint32_t(list.size());
    const int count = int(n - first < 8 ? n - first : 8);
    const Triangle* batch[8];
    for (int j = 0; j < count; ++j) batch[j] = &list[first + std::uint32_t(j)].corners;
    if (count <= 4)
        kernels.ray_x4(w, batch, count, lanes);
    else
        kernels.ray_x8(w, batch, count, lanes);
    return count;
}

// The candidates in list order until a batch starts beyond `stop`. kAny: the first hit (occlusion:
// stop is the segment's far end seen from the cell's origins, margin included: key_stop). Otherwise
// the closest (smallest t, at equal t smaller id); each better hit moves the stop to its own key
// (key_origin: s * org_k, s the sign of the ray's face, k its axis; step: |dir_k|; a hit at t lies at
// key key_origin + t * step).
template <bool kAny, bool kCount>
Hit scan_candidates(const TriangleKernels& kernels, std::span<const Candidate> list, const Ray& ray,
                    float key_origin, float step, float stop, QueryCounters* counters) {
    Hit best;
    WatertightRay w = make_watertight_ray(ray);
    const std::uint32_t n = std::uint32_t(list.size());
    for (std::uint32_t first = 0; first < n; first += 8) {
        if (list[first].key > stop) break;
        LaneHits lanes;
        const int count = test_batch(kernels, w, list, first, lanes);
        if constexpr (kCount) {
            counters->raycls.candidates += std::uint64_t(count);
            counters->triangle_tests += std::uint64_t(count);
        }
        for (std::uint32_t m = lanes.mask; m; m &= m - 1) {
            const int j = __builtin_ctz(m);
            const std::uint32_t id = list[first + std::uint32_t(j)].id;
            if (!(lanes.t[j] < best.t || (lanes.t[j] == best.t && id < best.triangle))) continue;
            best = Hit{lanes.t[j], id, lanes.u[j], lanes.v[j]};
            if constexpr (kAny) return best;
            w.tfar = best.t;
            stop = key_stop(key_origin, best.t, step);
        }
    }
    return best;
}

// Closest hit along the ray.
template <bool kCount>
Hit closest_candidate(const TriangleKernels& kernels, std::span<const Candidate> list, const Ray& ray,
                      float key_origin, float step, QueryCounters* counters) {
    return scan_candidates<false, kCount>(kernels, list, ray, key_origin, step, key_stop(key_origin, ray.tfar, step),
                                          counters);
}

// Any hit of the segment; candidates with keys beyond `stop` are not tested.
template <bool kCount>
bool any_candidate(const TriangleKernels& kernels, std::span<const Candidate> list, const Ray& ray, float stop,
                   QueryCounters* counters) {
    return scan_candidates<true, kCount>(kernels, list, ray, 0.0f, 0.0f, stop, counters).hit();
}

}  // namespace beamtrace::raycls
