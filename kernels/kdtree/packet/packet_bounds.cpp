#include "kdtree/packet/packet_bounds.hpp"

#include "simd/sse_lanes.hpp"

namespace beamtrace::kdtree {

namespace {

using B = sse::Floats;
using Mask = sse::Mask;
constexpr int W = int(B::size);

using sse::max_as_std;  // std::min and std::max lane by lane, as Interval's operator* takes them
using sse::min_as_std;

// widen() lane by lane: lo - (|lo| R + pad), hi + (|hi| R + pad).
void widen(B& lo, B& hi, const B& rel, const B& pad) {
    lo = lo - (xsimd::abs(lo) * rel + pad);
    hi = hi + (xsimd::abs(hi) * rel + pad);
}

}  // namespace

void BlockBounds::set(int p, const PacketBounds& b, float packet_reach) {
    for (int k = 0; k < 3; ++k) {
        org_lo[k][p] = b.org[k].lo;
        org_hi[k][p] = b.org[k].hi;
        inv_lo[k][p] = b.inv[k].lo;
        inv_hi[k][p] = b.inv[k].hi;
    }
    reach[p] = packet_reach;
}

std::uint32_t BlockBounds::meeting(const Box& box, float t0) const {
    const B rel(kRelativePad), pad_b(pad), t0_b(t0);
    std::uint32_t bits = 0;
    for (int base = 0; base < count; base += W) {
        B entry_lo[3], exit_hi[3];
        Mask miss(false);
        for (int k = 0; k < 3; ++k) {
            const B olo = B::load_aligned(org_lo[k] + base), ohi = B::load_aligned(org_hi[k] + base);
            const B ilo = B::load_aligned(inv_lo[k] + base), ihi = B::load_aligned(inv_hi[k] + base);
            // plane_t(k, face) for the entry and the exit face, as PacketBounds computes it.
            const float faces[2] = {sign[k] > 0 ? box.lower[k] : box.upper[k], sign[k] > 0 ? box.upper[k] : box.lower[k]};
            B lo[2], hi[2];
            for (int f = 0; f < 2; ++f) {
                B a = B(faces[f]) - ohi, b = B(faces[f]) - olo;
                widen(a, b, rel, pad_b);
                const B p0 = a * ilo, p1 = a * ihi, p2 = b * ilo, p3 = b * ihi;
                lo[f] = min_as_std(min_as_std(p0, p1), min_as_std(p2, p3));
                hi[f] = max_as_std(max_as_std(p0, p1), max_as_std(p2, p3));
                widen(lo[f], hi[f], rel, pad_b);
            }
            entry_lo[k] = lo[0];
            exit_hi[k] = hi[1];
            miss = miss | (exit_hi[k] < t0_b) | (entry_lo[k] > B::load_aligned(reach + base));
        }
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                if (a != b) miss = miss | (entry_lo[a] > exit_hi[b]);
        bits |= (~sse::bits_of(miss) & 0xFu) << base;
    }
    return count >= 32 ? bits : bits & ((1u << count) - 1u);
}

}  // namespace beamtrace::kdtree
