#pragma once
// Bit interleaving for Morton (Z-order) codes, shared by the ray keys of the stream tracer and of
// CRSH.
#include <cstdint>

namespace beamtrace {

// Written once for 32-bit unsigned words and for SIMD batches of 32-bit lanes (xsimd; the stream
// tracer's key kernels): every mask fits 31 bits, so signed lanes give the same bits.

// The low 16 bits of x spread over the even bits (two coordinates interleaved: a | b << 1).
template <class U>
constexpr U spread_bits_2(U x) {
    x = x & U(0xFFFF);
    x = (x | (x << 8)) & U(0x00FF00FF);
    x = (x | (x << 4)) & U(0x0F0F0F0F);
    x = (x | (x << 2)) & U(0x33333333);
    x = (x | (x << 1)) & U(0x55555555);
    return x;
}

// The low 10 bits of x spread over every third bit (three coordinates: a | b << 1 | c << 2).
template <class U>
constexpr U spread_bits_3(U x) {
    x = x & U(0x3FF);
    x = (x | (x << 16)) & U(0x030000FF);
    x = (x | (x << 8)) & U(0x0300F00F);
    x = (x | (x << 4)) & U(0x030C30C3);
    x = (x | (x << 2)) & U(0x09249249);
    return x;
}

static_assert(spread_bits_2(0xFFFFu) == 0x55555555u && spread_bits_3(0x3FFu) == 0x09249249u);

}  // namespace beamtrace
