#pragma once
// PackedIds: the triangle ids of a tile-BSP block, three bytes each (little-endian, entry k at
// bytes 3k .. 3k + 2), where they used to take four: a field holds at most 2^24 triangles
// (kMaxFieldTriangles; VisibilityField refuses more with an error). A tile entry is then 7 bytes
// (its 4-byte footprint and its id) instead of 8. Not in the paper (docs/vlf.md, "Compact tile
// entries").
//
// Reading id k loads the 4 bytes from 3k and drops the top one, so the id bytes of a block are
// followed by at least one more byte (words_of counts it). The AVX-512 kernels load 16 ids at once
// (packed_ids_impl.hpp); the others read them one at a time.
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace beamtrace::vlf {

inline constexpr std::size_t kMaxFieldTriangles = std::size_t(1) << 24;

struct PackedIds {
    const std::uint8_t* bytes = nullptr;

    std::uint32_t operator[](std::size_t k) const {
        std::uint32_t v;
        std::memcpy(&v, bytes + 3 * k, sizeof v);
        return v & 0xFFFFFFu;
    }
    PackedIds operator+(std::size_t k) const { return PackedIds{bytes + 3 * k}; }

    // The 32-bit words that hold `entries` ids and the byte read past the last.
    static constexpr std::size_t words_of(std::size_t entries) { return (3 * entries + 1 + 3) / 4; }
    // Writes ids (each < 2^24) packed into `out` (room for words_of(n) words; the padding is zeroed).
    static void pack(const std::uint32_t* ids, std::size_t n, std::uint32_t* out) {
        auto* b = reinterpret_cast<std::uint8_t*>(out);
        for (std::size_t k = 0; k < n; ++k) {
            b[3 * k] = std::uint8_t(ids[k]);
            b[3 * k + 1] = std::uint8_t(ids[k] >> 8);
            b[3 * k + 2] = std::uint8_t(ids[k] >> 16);
        }
        std::memset(b + 3 * n, 0, words_of(n) * 4 - 3 * n);
    }
};

}  // namespace beamtrace::vlf
