#pragma once
// The AVX-512 kernel of entry_closest_hit.hpp; included only by simd_avx512.cpp. Footprints are
// compared 16 at a time and the passing ids compressed into one vector; ids on the walk's tested
// list are masked out (one compare per listed id), the others appended to it; their corners are
// gathered (the ray's axis permutation folded into the gather offsets) and the library's
// watertight core tests them at once. The hitting lanes then compete as in the scalar reference.
#include <cstdint>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

#include "common/triangle_kernels_impl.hpp"
#include "vlf/build/packed_ids_impl.hpp"
#include "vlf/query/corner_load_impl.hpp"
#include "vlf/query/entry_closest_hit.hpp"

namespace beamtrace::vlf {
namespace {

#if defined(__AVX512BW__)
[[maybe_unused]] bool closest_entries_avx512(const WatertightRay& ray, const Triangle* triangles,
                                             const std::uint32_t* order, const std::uint32_t* footprints,
                                             PackedIds ids, std::uint32_t count, std::uint32_t ray_footprint,
                                             TestedIds& tested, Hit& best) {
    using Arch = xsimd::avx512bw;
    using B = xsimd::batch<float, Arch>;
    const __m512i r = _mm512_set1_epi32(int(ray_footprint));
    alignas(64) std::uint32_t candidates[2 * kEntryCandidates];
    std::uint32_t n = 0;
    for (std::uint32_t k = 0; k < count; k += 16) {
        const __mmask16 live = count - k >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << (count - k)) - 1u);
        const __m512i f = _mm512_maskz_loadu_epi32(live, footprints + k);
        const __mmask16 pass = _mm512_mask_cmpeq_epi32_mask(live, _mm512_max_epu8(f, r), r);
        if (pass == 0) continue;
        _mm512_storeu_si512(candidates + n, _mm512_maskz_compress_epi32(pass, load_packed_ids(ids + k, live)));
        n += std::uint32_t(__builtin_popcount(pass));
        if (n > kEntryCandidates) return false;
    }
    if (n == 0) return true;
    const __mmask16 valid = n == 16 ? __mmask16(0xFFFF) : __mmask16((1u << n) - 1u);
    const __m512i v = _mm512_maskz_load_epi32(valid, candidates);
    __mmask16 seen = 0;
    for (std::uint32_t c = 0; c < tested.count; ++c)
        seen |= _mm512_mask_cmpeq_epi32_mask(valid, v, _mm512_set1_epi32(int(tested.ids[c])));
    const __mmask16 fresh = valid & __mmask16(~seen);
    const auto added = std::uint32_t(__builtin_popcount(fresh));
    if (tested.count + added > tested.room) return false;
    if (added == 0) return true;
    // Compressed in a register and stored whole (the list has 16 words to spare): a compressing
    // store to memory is microcoded, and slow, on some processors (AMD Zen 4).
    _mm512_storeu_si512(tested.ids + tested.count, _mm512_maskz_compress_epi32(fresh, v));
    tested.count += added;
    const simd::Corners<Arch> k = ray_corners(ray, triangles, candidates, fresh);
    LaneHits lanes;
    const std::uint32_t bits = simd::watertight_core<Arch>(k, B(ray.sx), B(ray.sy), B(ray.sz), B(ray.tnear),
                                                           B(ray.tfar), std::uint32_t(fresh), lanes, 0);
    for (std::uint32_t m = bits; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        if (nearer_hit(lanes.t[i], candidates[i], best, order))
            best = Hit{lanes.t[i], candidates[i], lanes.u[i], lanes.v[i]};
    }
    return true;
}
#endif

}  // namespace
}  // namespace beamtrace::vlf
