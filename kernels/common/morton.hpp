#pragma once
// Bit interleaving for Morton (Z-order) codes, shared by the ray keys of the stream tracer and of
// CRSH.
#include <cstdint>

namespace beamtrace {

// The low 16 bits of x spread over the even bits (two coordinates interleaved: a | b << 1).
constexpr std::uint32_t spread_bits_2(std::uint32_t x) {
    x &= 0xFFFFu;
    x = (x | (x << 8)) & 0x00FF00FFu;
    x = (x | (x << 4)) & 0x0F0F0F0Fu;
    x = (x | (x << 2)) & 0x33333333u;
    x = (x | (x << 1)) & 0x55555555u;
    return x;
}

// The low 10 bits of x spread over every third bit (three coordinates: a | b << 1 | c << 2).
constexpr std::uint32_t spread_bits_3(std::uint32_t x) {
    x &= 0x3FFu;
    x = (x | (x << 16)) & 0x030000FFu;
    x = (x | (x << 8)) & 0x0300F00Fu;
    x = (x | (x << 4)) & 0x030C30C3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
}

static_assert(spread_bits_2(0xFFFFu) == 0x55555555u && spread_bits_3(0x3FFu) == 0x09249249u);

}  // namespace beamtrace
