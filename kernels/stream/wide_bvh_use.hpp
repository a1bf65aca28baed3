#pragma once
// Rays traced alone through the stream tracer's wide BVH (docs/streams.md, step 6c; docs/wide_bvh.md).
#include <cstddef>
#include <cstdint>

#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "bvh/wide_bvh.hpp"
#include "common/query_runner.hpp"

namespace beamtrace::stream {

// An answer as the caller's span holds it: the hit, or whether there is one.
template <bool kOcclusion, class Out>
void store_answer(Out& slot, const Hit& h) {
    if constexpr (kOcclusion)
        slot = h.hit();
    else
        slot = h;
}

// Rays traced alone through the wide BVH, a task's share of them.
constexpr std::size_t kAloneGrain = 1024;

// The wide BVH with its kernels (StreamTracer::bvh_, bvh_kernels_); bvh null: none.
struct WideBvhUse {
    const bvh::WideBvh* bvh;
    const bvh::WideBvhKernels* kernels;

    // One ray through it (counted when kCount).
    template <bool kOcclusion, bool kCount>
    Hit trace(const Ray& ray, QueryCounters* c) const {
        if constexpr (kCount)
            return (kOcclusion ? kernels->occluded_counted : kernels->intersect_counted)(*bvh, ray, c);
        return (kOcclusion ? kernels->occluded : kernels->intersect)(*bvh, ray);
    }

    // Rays [b, e) one by one (ray(k): the k-th), their answers to out[b .. e).
    template <bool kOcclusion, bool kCount, class RayAt, class Out>
    void trace_range(std::size_t b, std::size_t e, const RayAt& ray, Out* out, QueryCounters* c) const {
        for (std::size_t k = b; k < e; ++k) store_answer<kOcclusion>(out[k], trace<kOcclusion, kCount>(ray(k), c));
    }

    // All n of them on the options' threads, counted when options.counters is set.
    template <bool kOcclusion, class RayAt, class Out>
    void trace_all(std::size_t n, const QueryOptions& options, const RayAt& ray, Out* out) const {
        run_query(n, options, kAloneGrain, [&](std::size_t b, std::size_t e, QueryCounters* c) {
            if (c)
                trace_range<kOcclusion, true>(b, e, ray, out, c);
            else
                trace_range<kOcclusion, false>(b, e, ray, out, nullptr);
        });
    }
};

}  // namespace beamtrace::stream
