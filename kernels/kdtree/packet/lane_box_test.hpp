#pragma once
// Leaf culling with the packet's own rays (MLRTA section 4.3, "at leaves, cull ... whose box misses
// the packet"): the slab test of every active ray's current segment [tnear, tfar] against a leaf's
// box, 16 lanes at once. Interval bounds of the whole packet (the paper's test (2)) keep a leaf that
// the hull of a sparse packet touches; this keeps it only if some ray does (shadow packets from a
// light towards the scattered hit points of 16 pixels: two thirds of the leaves the interval test
// keeps on `room`). `lanes_meeting_box` is the scalar reference; the SIMD kernels
// (kernels/simd/kernels_<isa>.cpp, PacketKernels::lane_box) do the same operations in the same order, so their bits are
// its bits.
#include <cmath>
#include <cstdint>

#include "beamtrace/ray.hpp"
#include "common/interval.hpp"

namespace beamtrace::kdtree {

// Per-packet set-up: origins, reciprocal directions and starts of the 16 lanes.
struct alignas(64) LaneBoxRays {
    float org[3][16];
    float inv[3][16];
    float tnear[16];
    float pad = 0.0f;  // absolute widening of the box (the scene's scale * 2^-20)

    // The box is grown by pad on every side and the segment's ends by a relative 2^-16, so that no
    // rounding can drop a ray that meets the box (the directions' components must be non-zero).
    bool meets(int i, float tfar, const Box& box) const {
        float t0 = tnear[i], t1 = tfar;
        for (int k = 0; k < 3; ++k) {
            const float a = ((box.lower[k] - pad) - org[k][i]) * inv[k][i];
            const float b = ((box.upper[k] + pad) - org[k][i]) * inv[k][i];
            t0 = std::max(t0, std::min(a, b));
            t1 = std::min(t1, std::max(a, b));
        }
        return t0 - std::fabs(t0) * kRelativePad <= t1 + std::fabs(t1) * kRelativePad;
    }
};

LaneBoxRays make_lane_box_rays(const Packet16& packet, float pad);
void make_lane_box_rays(const Packet16& packet, float pad, LaneBoxRays& out);  // the same, in place

// Bit i (of `lanes`) set when ray i's segment [tnear, tfar[i]] meets the box.
std::uint32_t lanes_meeting_box(const LaneBoxRays& s, const float* tfar, std::uint32_t lanes, const Box& box);

using LaneBoxKernel = std::uint32_t (*)(const LaneBoxRays& s, const float* tfar, std::uint32_t lanes, const Box& box);

}  // namespace beamtrace::kdtree
