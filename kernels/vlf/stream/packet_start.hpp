#pragma once
// The start of a packet query, in two stages so that a stream of packets can run them ahead of
// the walks (ray_stream.cpp): start_packet makes the 16 lookups (SIMD) and asks the cache for each
// ray's first tile entry; prefetch_first_blocks then reads those entries and asks for the start of
// each tile's block. A lone packet runs both back to back, so the cache misses of its 16 rays
// overlap instead of following one another; a stream runs them one and two packets ahead of the
// walks, so the misses are resolved by the time the walks need the data.
#include "vlf/stream/packet_lookup.hpp"
#include "vlf/build/parallel_subfield.hpp"
#include "vlf/vlf_impl.hpp"

namespace beamtrace::vlf {

struct PacketStart {
    PacketLookup lookup;
    const ParallelSubfield* psf[16];  // of the valid lanes (built now if needed)
    std::uint32_t tile[16];           // of the valid lanes: the tile where the segment starts
};

// first_tiles: also what a segment inside its first tile needs (PacketLookup::one_tile ...).
void lookup_packet(const VisibilityField::Impl& f, const Packet16& p, PacketLookup& out, bool first_tiles = false);
void start_packet(const VisibilityField::Impl& f, const Packet16& p, PacketStart& s);
void prefetch_first_blocks(const PacketStart& s);

}  // namespace beamtrace::vlf
