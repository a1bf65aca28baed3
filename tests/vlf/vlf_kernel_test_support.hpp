#pragma once
// What the VLF kernel tests share: the SIMD instruction sets this CPU has, bit patterns for exact
// comparisons, ids packed as a tile block holds them, and random footprints (tile_footprint.hpp).
#include <algorithm>
#include <bit>
#include <cstdint>
#include <random>
#include <vector>

#include "simd/isa.hpp"
#include "vlf/build/packed_ids.hpp"
#include "vlf/query/tile_footprint.hpp"

namespace beamtrace::vlf::test_support {

// ids packed as a tile block holds them (packed_ids.hpp), in a vector of exactly the words they take.
inline std::vector<std::uint32_t> packed(const std::vector<std::uint32_t>& ids) {
    std::vector<std::uint32_t> words(PackedIds::words_of(ids.size()));
    PackedIds::pack(ids.data(), ids.size(), words.data());
    return words;
}
inline PackedIds view(const std::vector<std::uint32_t>& words) {
    return PackedIds{reinterpret_cast<const std::uint8_t*>(words.data())};
}

inline std::vector<Isa> simd_isas() {
    std::vector<Isa> out;
    for (Isa isa : {Isa::sse42, Isa::avx2, Isa::avx512})
        if (isa_available(isa)) out.push_back(isa);
    return out;
}

template <class T>
std::uint64_t bits(T v) {
    if constexpr (sizeof(T) == 8)
        return std::bit_cast<std::uint64_t>(v);
    else
        return std::bit_cast<std::uint32_t>(v);
}

// A triangle's footprint: a random box on the tile's 256 x 256 lattice.
inline std::uint32_t random_triangle_footprint(std::mt19937& rng) {
    const std::uint32_t x0 = rng() % 256, y0 = rng() % 256;
    const std::uint32_t x1 = x0 + rng() % (256 - x0), y1 = y0 + rng() % (256 - y0);
    return x0 | (y0 << 8) | ((255 - x1) << 16) | ((255 - y1) << 24);
}

// A ray's footprint: a random square of side below max_side, or (one time in three) the whole tile.
inline std::uint32_t random_ray_footprint(std::mt19937& rng, std::uint32_t max_side) {
    const FootprintLattice lattice{0.0, 0.0, 1.0};
    const double x = double(rng() % 256), y = double(rng() % 256);
    const double size = double(rng() % 3 == 0 ? 255 : rng() % max_side);
    return lattice.ray(x, std::min(255.0, x + size), y, std::min(255.0, y + size));
}

}  // namespace beamtrace::vlf::test_support
