#pragma once
// The sorting step of the stream tracer: the rays' 32-bit keys with their indices sorted by the
// library's radix sort (common/radix_sort.hpp: stable, digits of up to 11 bits, passes whose digit
// all keys share skipped, on `parts` threads of the caller's TBB arena), in linear time. Rays keyed
// by their origin's cell are sorted within their cell by a hash of their exact origin too, so that
// the rays of one origin come out next to each other (but where two origins of a cell share a hash);
// then the rays gathered into that order. The tracer does both in one (ray_sort.hpp); these are its
// reference and the sort of other callers.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include <immintrin.h>

#include "beamtrace/ray.hpp"
#include "stream/ray_keys.hpp"

namespace beamtrace::stream {

// The sort's (key, origin hash, index) words and its scratch, kept by the caller across calls.
struct SortBuffers {
    std::vector<std::uint64_t> records, scratch;
};

// A hash of a ray's origin, bit for bit (equal origins, equal hashes).
inline std::uint32_t origin_hash(const Ray& ray) {
    std::uint32_t h = std::bit_cast<std::uint32_t>(ray.org.x) * 0x9E3779B1u;
    h ^= std::bit_cast<std::uint32_t>(ray.org.y) * 0x85EBCA77u;
    h ^= std::bit_cast<std::uint32_t>(ray.org.z) * 0xC2B2AE3Du;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    return h ^ (h >> 12);
}

// How many of the origin hash's bits a sort of n rays uses: those its 64-bit words have room for
// beside the 32-bit key and the index, at most kMaxHashBits (four radix passes in all).
inline constexpr int kMaxHashBits = 12;
inline int hash_bits(std::size_t n) {
    const int index_bits = std::max(1, int(std::bit_width(n > 1 ? n - 1 : std::size_t{1})));
    return std::clamp(32 - index_bits, 0, kMaxHashBits);
}

// The sort's 64-bit words: the key in the top 32 bits, then hash_bits(n) bits of the origin's hash
// (rays keyed by their origin's cell, when the stream has any and hashes are given), then the index.
struct SortWords {
    int hash_bits = 0;
    int index_bits = 32;
    std::uint64_t index_mask = 0xFFFFFFFFu;

    SortWords(std::span<const std::uint32_t> keys, std::span<const std::uint32_t> hashes);
    std::uint64_t word(std::uint32_t key, std::uint32_t hash, std::size_t index) const {
        const std::uint64_t h = hash_bits == 0 || (key & kPencilBit) ? 0 : hash >> (32 - hash_bits);
        return (std::uint64_t(key) << 32) | (h << index_bits) | index;
    }
    std::uint64_t value(std::uint64_t w) const { return w >> index_bits; }  // what the words sort by
    std::uint32_t index(std::uint64_t w) const { return std::uint32_t(w & index_mask); }
    static std::uint32_t key(std::uint64_t w) { return std::uint32_t(w >> 32); }
};

// Fills `order` with 0 .. keys.size()-1 sorted by key and, among rays of one origin-cell key (bit 31
// clear), by the top hash_bits(n) bits of hashes[i] (origin_hash of the key's ray); equal keys (and
// hashes) keep their input order. sorted_keys[k] = keys[order[k]]. `hashes` may be empty (by key
// alone).
void sort_by_key(std::span<const std::uint32_t> keys, std::span<const std::uint32_t> hashes,
                 std::span<std::uint32_t> order, std::span<std::uint32_t> sorted_keys, int parts, SortBuffers& buffers);

// Streams of at least this many rays (32 MB) are written out with streaming stores (store_ray): the
// sorted rays are written once, beyond the caches, and a plain store would first read each line.
inline constexpr std::size_t kStreamingRays = std::size_t{1} << 20;

// *to = from, by streaming stores when `streaming` (to 16-byte aligned; an _mm_sfence after the last).
inline void store_ray(Ray* to, const Ray& from, bool streaming) {
    static_assert(sizeof(Ray) == 8 * sizeof(float));  // 8 floats, no padding
    if (!streaming) {
        *to = from;
        return;
    }
    const auto* f = reinterpret_cast<const float*>(&from);
    auto* t = reinterpret_cast<float*>(to);
    _mm_stream_ps(t, _mm_loadu_ps(f));
    _mm_stream_ps(t + 4, _mm_loadu_ps(f + 4));
}

// out[k] = rays[order[k]] for k in [begin, end): the rays in sorted order. The reads are random
// over the whole stream, so each is asked for `kGatherAhead` rays before it is copied (their misses
// overlap).
inline constexpr std::size_t kGatherAhead = 16;
void gather_in_order(std::span<const Ray> rays, std::span<const std::uint32_t> order, std::size_t begin,
                     std::size_t end, std::span<Ray> out);

}  // namespace beamtrace::stream
