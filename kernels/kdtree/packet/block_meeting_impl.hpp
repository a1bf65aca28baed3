#pragma once
// Test (2) of interval traversal for every packet of a block at once (BlockBounds, PacketKernels::
// block_meeting) written once over xsimd's Arch: 4, 8 or 16 packets a step (SSE4.2, AVX2, AVX-512),
// each lane doing packet_misses_box's operations in its order, so every width decides as the scalar
// reference does, bit for bit. Included only by the per-ISA units (simd/isa_unit.hpp).
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "kdtree/packet/packet_bounds.hpp"
#include "simd/lane_bits.hpp"
#include "simd/lane_folds.hpp"

namespace beamtrace::kdtree::simd_impl {

// Bit p set when packet p of [0, block.count) does not miss the box (BlockBounds::meeting's contract).
template <class Arch>
std::uint32_t block_meeting(const BlockBounds& block, const Box& box, float t0) {
    using B = xsimd::batch<float, Arch>;
    using M = xsimd::batch_bool<float, Arch>;
    constexpr int W = int(B::size);
    const B rel(kRelativePad), pad(block.pad), t0_b(t0);
    // widen() lane by lane: lo - (|lo| R + pad), hi + (|hi| R + pad).
    const auto widen = [&](B& lo, B& hi) {
        lo = lo - (xsimd::abs(lo) * rel + pad);
        hi = hi + (xsimd::abs(hi) * rel + pad);
    };
    std::uint32_t bits = 0;
    for (int base = 0; base < block.count; base += W) {
        // Columns past count were never set (a block of 4 packets fills a quarter of an AVX-512
        // register): zeros there, never the stack's old bits (denormals and NaNs cost a microcode
        // assist an operation; the shadow rays of a stream ran 30 % slower on them).
        const std::uint32_t used = (1u << (block.count - base < W ? block.count - base : W)) - 1u;
        const M on = simd::lanes_on<Arch>(used);
        const auto column = [&](const float* at) { return xsimd::select(on, B::load_aligned(at + base), B(0.0f)); };
        B entry_lo[3], exit_hi[3];
        M miss(false);
        for (int k = 0; k < 3; ++k) {
            const B olo = column(block.org_lo[k]), ohi = column(block.org_hi[k]);
            const B ilo = column(block.inv_lo[k]), ihi = column(block.inv_hi[k]);
            // plane_t(k, face) for the entry and the exit face, as PacketBounds computes it.
            const float faces[2] = {block.sign[k] > 0 ? box.lower[k] : box.upper[k],
                                    block.sign[k] > 0 ? box.upper[k] : box.lower[k]};
            B lo[2], hi[2];
            for (int f = 0; f < 2; ++f) {
                B a = B(faces[f]) - ohi, b = B(faces[f]) - olo;
                widen(a, b);
                const B p0 = a * ilo, p1 = a * ihi, p2 = b * ilo, p3 = b * ihi;
                lo[f] = simd::min_as_std(simd::min_as_std(p0, p1), simd::min_as_std(p2, p3));
                hi[f] = simd::max_as_std(simd::max_as_std(p0, p1), simd::max_as_std(p2, p3));
                widen(lo[f], hi[f]);
            }
            entry_lo[k] = lo[0];
            exit_hi[k] = hi[1];
            miss = miss | (exit_hi[k] < t0_b) | (entry_lo[k] > column(block.reach));
        }
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                if (a != b) miss = miss | (entry_lo[a] > exit_hi[b]);
        bits |= simd::lane_bits<Arch>(~miss) << base;
    }
    return bits & ((1u << block.count) - 1u);  // count <= BlockBounds::kPackets = 16
}

}  // namespace beamtrace::kdtree::simd_impl
