#pragma once
// Triangle culling for a packet whose rays share one origin (MLRTA leaf culling, finer than the
// leaf box): the range of every slope dir_j / |dir_m| over the packet (m the main axis), widened.
// A triangle lies outside the frustum when all three corners are in front of the origin and beyond
// the same side of one slope range. `misses` is the scalar reference; the SIMD kernels
// (kernels/simd/kernels_<isa>.cpp) decide up to 16 triangles at once with the same operations in the
// same order, so their decisions are the reference's, bit for bit.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"
#include "common/interval.hpp"

namespace beamtrace::kdtree {

struct OneOriginFrustum {
    bool valid = false;
    int m = 0;           // main axis
    int j0 = 1, j1 = 2;  // the two other axes
    float sm = 1.0f;     // sign of the rays' main component
    Float3 origin;
    Interval slope[3] = {};  // zero when there is no frustum (valid false)
    // The farthest any ray of the packet reaches along the main axis (tfar * |dir_m|, widened):
    // a triangle whose corners all lie beyond it is past every segment's end (shadow rays end just
    // in front of the surface they start from). +infinity when some segment is unbounded.
    float reach = kInfinity;

    // Bound on the rounding of a corner's slope, per unit of 1/w: the subtractions lose up to an
    // ulp of the coordinates involved, the reciprocal and the products a few ulps of the slope; the
    // bound allows 2^-21 of every magnitude involved (16 ulps of each).
    static constexpr float kSlopeError = 1.0f / 2097152.0f;
    // Bound on the rounding of a corner's main-axis distance w, per unit of the coordinates
    // involved (2^-20: 8 ulps).
    static constexpr float kDepthError = 1.0f / 1048576.0f;

    bool misses(const Triangle& t) const {
        const Float3* corner = &t.v0;
        float q[3][2], e[3][2];
        bool beyond = true;
        for (int v = 0; v < 3; ++v) {
            const float cm = corner[v][m] - origin[m];
            const float w = cm * sm;        // distance in front of the origin along the main axis
            if (!(w > 0.0f)) return false;  // a corner behind the origin: no decision
            beyond = beyond && w - (std::fabs(corner[v][m]) + std::fabs(origin[m])) * kDepthError > reach;
            const float inv_w = 1.0f / w;
            const float err = kSlopeError * inv_w;
            const float depth = std::fabs(corner[v][m]) + std::fabs(origin[m]);
            const int js[2] = {j0, j1};
            for (int a = 0; a < 2; ++a) {
                const int j = js[a];
                q[v][a] = (corner[v][j] - origin[j]) * inv_w;  // the corner's slope c_j / |c_m|
                const float scale = (std::fabs(corner[v][j]) + std::fabs(origin[j])) + std::fabs(q[v][a]) * depth;
                e[v][a] = scale * err;
            }
        }
        if (beyond) return true;
        const int js[2] = {j0, j1};
        for (int a = 0; a < 2; ++a) {
            const Interval s = slope[js[a]];
            bool below = true, above = true;
            for (int v = 0; v < 3; ++v) {
                below = below && q[v][a] + e[v][a] < s.lo;
                above = above && q[v][a] - e[v][a] > s.hi;
            }
            if (below || above) return true;
        }
        return false;
    }
};

// The frustum of the lanes of `mask`, which must all point into one sign octant with no zero
// component; `valid` is false (nothing culled) unless they share one origin. Four lanes at a time
// (SSE): the reference of the kernels' set-up (packet_setup_kernels.hpp).
OneOriginFrustum make_one_origin_frustum(const Packet16& packet, std::uint32_t mask);

// The scalar parts of make_one_origin_frustum, which the SIMD kernels share: the main axis, the other
// two, the sign and the origin from lane `first`; then the slopes from the ranges of dir_j0 / |dir_m|
// and dir_j1 / |dir_m| over the lanes, widened, the reach from the largest tfar |dir_m|, and `valid`.
void set_frustum_axes(OneOriginFrustum& f, const Packet16& packet, int first);
void finish_frustum(OneOriginFrustum& f, Interval q0, Interval q1, float reach);

// The corners of the tree's leaf triangles as nine rows (row c = corner c / 3, axis c % 3), one
// float per leaf triangle in the leaves' order: coordinate c of leaf triangle r is
// at[c * stride + r]. Each row is followed by at least 16 padding floats (zeros), so that a kernel
// may load a whole register from any triangle of the list. What the SIMD culling reads without
// gathering (packet_tables.hpp).
struct CornerRows {
    const float* at = nullptr;
    std::size_t stride = 0;
    float get(std::size_t r, int c) const { return at[std::size_t(c) * stride + r]; }
    Triangle triangle(std::size_t r) const {
        return {
            {get(r, 0), get(r, 1), get(r, 2)}, {get(r, 3), get(r, 4), get(r, 5)}, {get(r, 6), get(r, 7), get(r, 8)}};
    }
};

// Bit i set when the frustum misses leaf triangle first + i of `rows`, for i < n (n <= 16; a
// leaf's triangles are consecutive).
using FrustumCullKernel = std::uint32_t (*)(const OneOriginFrustum& f, const CornerRows& rows, std::size_t first,
                                            int n);

// The scalar reference of the kernel, triangle by triangle with OneOriginFrustum::misses. The SIMD
// kernels (PacketKernels::frustum_cull, packet_kernels.hpp) decide 4, 8 or 16 at a time.
std::uint32_t frustum_misses(const OneOriginFrustum& f, const CornerRows& rows, std::size_t first, int n);

}  // namespace beamtrace::kdtree
