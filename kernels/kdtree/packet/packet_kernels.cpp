// The scalar table of packet traversal's kernels: the references.
#include "kdtree/packet/packet_kernels.hpp"

namespace beamtrace {

template <>
const kdtree::PacketKernels& simd::table<kdtree::PacketKernels, Isa::scalar>() {
    static constexpr kdtree::PacketKernels kScalar{Isa::scalar, kdtree::frustum_misses, kdtree::lanes_meeting_box,
                                                  kdtree::kReferenceSetup, kdtree::block_meeting_reference};
    return kScalar;
}

}  // namespace beamtrace
