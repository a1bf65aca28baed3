#pragma once
// The SIMD kernels of packet traversal, one table per instruction set (simd/dispatch.hpp): the
// culling of a leaf's triangles by the frustum of a one-origin packet (one_origin_frustum.hpp) and
// the per-lane slab test of leaf boxes (lane_box_test.hpp), the per-packet set-up
// (packet_setup_kernels.hpp) and test (2) for a block of packets (packet_bounds.hpp). The scalar
// table holds the references.
#include "kdtree/packet/lane_box_test.hpp"
#include "kdtree/packet/packet_bounds.hpp"
#include "kdtree/packet/one_origin_frustum.hpp"
#include "kdtree/packet/packet_setup_kernels.hpp"
#include "simd/dispatch.hpp"

namespace beamtrace::kdtree {

struct PacketKernels {
    Isa isa;
    FrustumCullKernel frustum_cull;  // on the corner rows; scalar: frustum_misses; SSE4.2 4, AVX2 8, AVX-512 16 a step
    LaneBoxKernel lane_box;          // scalar: lanes_meeting_box
    PacketSetupKernels setup;        // scalar: kReferenceSetup; SSE4.2 4, AVX2 8, AVX-512 16 lanes a step
    BlockMeetingKernel block_meeting;  // scalar: block_meeting_reference; SSE4.2 4, AVX2 8, AVX-512 16 packets a step
};

}  // namespace beamtrace::kdtree

BEAMTRACE_KERNEL_TABLE(beamtrace::kdtree::PacketKernels);
