// Run-time choice of the packet lookup kernel.
#include "vlf/packet_lookup.hpp"

namespace beamtrace::vlf {

LookupPacketFn lookup_packet_kernel(Isa isa) {
    switch (isa) {
        case Isa::scalar: return nullptr;
        case Isa::sse42: return lookup_sse42::lookup_packet;
        case Isa::avx2: return lookup_avx2::lookup_packet;
        case Isa::avx512: return lookup_avx512::lookup_packet;
    }
    return nullptr;
}

}  // namespace beamtrace::vlf
