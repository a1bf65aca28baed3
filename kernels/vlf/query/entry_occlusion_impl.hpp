#pragma once
// The AVX-512 kernel of entry_occlusion.hpp; included only by simd_avx512.cpp. Footprints are
// compared 16 at a time and the passing ids compressed into one vector; duplicates (a later lane
// holding an id an earlier one holds) are dropped with a conflict detection; the 16 triangles'
// corners are gathered, the ray's axis permutation folded into the gather offsets, and the
// library's watertight core (common/triangle_kernels_impl.hpp) tests them all at once. The lowest
// hitting lane is the first hitting candidate in entry order, as in the scalar reference.
#include <cstdint>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

#include "common/triangle_kernels_impl.hpp"
#include "vlf/build/packed_ids_impl.hpp"
#include "vlf/query/corner_load_impl.hpp"
#include "vlf/query/entry_occlusion.hpp"

namespace beamtrace::vlf {
namespace {

#if defined(__AVX512BW__) && defined(__AVX512CD__)
[[maybe_unused]] EntriesAnswer occlude_entries_avx512(const WatertightRay& ray, const Triangle* triangles,
                                                      const std::uint32_t* footprints, PackedIds ids,
                                                      std::uint32_t count, std::uint32_t ray_footprint, bool distinct,
                                                      std::uint32_t* hit) {
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
        const __m512i v = _mm512_maskz_compress_epi32(pass, load_packed_ids(ids + k, live));
        _mm512_storeu_si512(candidates + n, v);
        n += std::uint32_t(__builtin_popcount(pass));
        // More than kEntryCandidates passing entries: repeats may still bring the distinct ids
        // down to kEntryCandidates; the reference decides (rare).
        if (n > kEntryCandidates)
            return occlude_entries_scalar(ray, triangles, footprints, ids, count, ray_footprint, distinct, hit);
    }
    if (n == 0) return EntriesAnswer::clear;
    const __mmask16 valid = n == 16 ? __mmask16(0xFFFF) : __mmask16((1u << n) - 1u);
    const __m512i v = _mm512_maskz_load_epi32(valid, candidates);
    __mmask16 first = valid;
    if (!distinct) {
        const __m512i conflicts = _mm512_maskz_conflict_epi32(valid, v);
        first = _mm512_mask_testn_epi32_mask(valid, conflicts, conflicts);
    }
    const simd::Corners<Arch> k = ray_corners(ray, triangles, candidates, first);
    LaneHits lanes;
    const std::uint32_t bits = simd::watertight_core<Arch>(k, B(ray.sx), B(ray.sy), B(ray.sz), B(ray.tnear),
                                                           B(ray.tfar), std::uint32_t(first), lanes, 0);
    if (bits == 0) return EntriesAnswer::clear;
    *hit = candidates[__builtin_ctz(bits)];
    return EntriesAnswer::hit;
}
#endif

}  // namespace
}  // namespace beamtrace::vlf
