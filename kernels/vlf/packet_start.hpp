#pragma once
// The start of a packet query: the 16 lookups (SIMD), then the memory the 16 walks begin with is
// requested for all of them before the first walk starts (the first tile's entry, the first 256
// bytes of its block), so that the cache misses of different rays overlap instead of following
// one another. Shared by the packet queries and the binned ray streams.
#include "vlf/packet_lookup.hpp"
#include "vlf/parallel_subfield.hpp"
#include "vlf/vlf_impl.hpp"

namespace beamtrace::vlf {

struct PacketStart {
    PacketLookup lookup;
    const ParallelSubfield* psf[16];  // of the valid lanes (built now if needed)
};

void lookup_packet(const VisibilityField::Impl& f, const Packet16& p, PacketLookup& out);
void start_packet(const VisibilityField::Impl& f, const Packet16& p, PacketStart& s);

}  // namespace beamtrace::vlf
