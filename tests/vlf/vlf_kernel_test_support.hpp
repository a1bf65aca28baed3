#pragma once
// What the VLF kernel tests share: the SIMD instruction sets this CPU has, bit patterns for exact
// comparisons, and ids packed as a tile block holds them.
#include <bit>
#include <cstdint>
#include <vector>

#include "simd/isa.hpp"
#include "vlf/build/packed_ids.hpp"

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

}  // namespace beamtrace::vlf::test_support
