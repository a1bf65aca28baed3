#pragma once
// packet_set_ranges (packet_set_ranges.hpp) W lanes a step (4 with SSE4.2, 8 with AVX2, 16 with
// AVX-512): per lane the reference's operations in its order (contraction is off), folded into
// W-wide minima and maxima (std::min / std::max lane by lane: a NaN is passed over) and reduced at
// the end. With zeros folded as +0 and NaNs passed over, the order of the folds does not change a
// minimum or a maximum: the reference's ranges bit for bit (tests/kdtree/packet_setup_kernels_test.cpp). Included only by the per-ISA units.
#include <algorithm>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "common/ray_validity_impl.hpp"
#include "kdtree/packet/packet_set_ranges.hpp"
#include "simd/lane_bits.hpp"
#include "simd/lane_folds.hpp"

namespace beamtrace::kdtree::simd_impl {

template <class Arch>
void packet_set_ranges(std::span<const Packet16* const> packets, PacketSetRanges& out) {
    using B = xsimd::batch<float, Arch>;
    using beamtrace::simd::lane_bits;
    using beamtrace::simd::lanes_on;
    using beamtrace::simd::sign_bits;
    constexpr int W = int(B::size);
    constexpr std::uint32_t kLanes = (1u << W) - 1u;
    out = PacketSetRanges{};
    const B inf(kInfinity), ninf(-kInfinity), zero(0.0f);
    // lo / hi of: dir 0-2, start 3-5, length 6, near 7, far 8.
    B lo[9], hi[9];
    for (int j = 0; j < 9; ++j) {
        lo[j] = inf;
        hi[j] = ninf;
    }
    std::uint32_t zeros = 0, negative[3] = {0, 0, 0}, positive[3] = {0, 0, 0};
    bool same = true;
    B lead[3] = {zero, zero, zero};
    constexpr std::size_t kAhead = 2;  // packets read ahead (a set's packets are usually read here first)
    for (std::size_t n = 0; n < packets.size(); ++n) {
        if (n + kAhead < packets.size()) {
            const char* next = reinterpret_cast<const char*>(packets[n + kAhead]);
            for (std::size_t line = 0; line < sizeof(Packet16); line += 64) __builtin_prefetch(next + line);
        }
        const Packet16& p = *packets[n];
        const float* d[3] = {p.dir_x, p.dir_y, p.dir_z};
        const float* o[3] = {p.org_x, p.org_y, p.org_z};
        std::uint32_t segment = 0;
        for (int base = 0; base < 16; base += W)
            segment |= lane_bits<Arch>(beamtrace::simd::describes_segment_lanes<Arch>(
                           B::load_unaligned(o[0] + base), B::load_unaligned(o[1] + base),
                           B::load_unaligned(o[2] + base), B::load_unaligned(d[0] + base),
                           B::load_unaligned(d[1] + base), B::load_unaligned(d[2] + base),
                           B::load_unaligned(p.tnear + base), B::load_unaligned(p.tfar + base)))
                       << base;
        const std::uint32_t active = p.active & 0xFFFFu & segment;
        if (active == 0) continue;
        if (out.rays == 0) {
            const int i = __builtin_ctz(active);
            out.main_axis = dominant_axis(d[0][i], d[1][i], d[2][i]);
            out.first_origin = Float3{o[0][i], o[1][i], o[2][i]};
            for (int k = 0; k < 3; ++k) lead[k] = B(o[k][i]);
        }
        out.rays += std::uint32_t(__builtin_popcount(active));
        const float* main = d[out.main_axis];
        for (int base = 0; base < 16; base += W) {
            const std::uint32_t bits = (active >> base) & kLanes;
            if (bits == 0) continue;
            const auto on = lanes_on<Arch>(bits);
            auto fold = [&](int j, const B& v) {
                const B canonical = v + zero;  // -0 as +0
                lo[j] = beamtrace::simd::min_as_std(lo[j], xsimd::select(on, canonical, inf));  // a NaN is passed over
                hi[j] = beamtrace::simd::max_as_std(hi[j], xsimd::select(on, canonical, ninf));
            };
            const B tnear = B::load_unaligned(p.tnear + base), tfar = B::load_unaligned(p.tfar + base);
            for (int k = 0; k < 3; ++k) {
                const B v = B::load_unaligned(d[k] + base), ov = B::load_unaligned(o[k] + base);
                zeros |= lane_bits<Arch>(v == zero) & bits;
                const std::uint32_t s = sign_bits<Arch>(v) & bits;
                negative[k] |= s;
                positive[k] |= ~s & bits;
                same = same && (lane_bits<Arch>(ov == lead[k]) & bits) == bits;
                fold(k, v);
                fold(3 + k, ov + v * tnear);
            }
            const B mag = xsimd::abs(B::load_unaligned(main + base));
            fold(6, (tfar - tnear) * mag);
            fold(7, tnear * mag);
            fold(8, tfar * mag);
        }
    }
    if (out.rays == 0) return;
    out.same_origin = same;
    out.zero = zeros != 0;
    for (int k = 0; k < 3; ++k) out.signs[k] = (negative[k] ? 1u : 0u) | (positive[k] ? 2u : 0u);
    Interval r[9];
    for (int j = 0; j < 9; ++j) {
        alignas(64) float l[W], h[W];
        lo[j].store_aligned(l);
        hi[j].store_aligned(h);
        r[j] = {l[0], h[0]};
        for (int i = 1; i < W; ++i) r[j] = {std::min(r[j].lo, l[i]), std::max(r[j].hi, h[i])};
    }
    for (int k = 0; k < 3; ++k) {
        out.dir[k] = r[k];
        out.start[k] = r[3 + k];
    }
    out.length = r[6];
    out.near = r[7];
    out.far = r[8];
}

}  // namespace beamtrace::kdtree::simd_impl
