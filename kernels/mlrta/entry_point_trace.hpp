#pragma once
// A tile's packets finish with the kd-tree's packet traversal (kdtree/packet), started at the tile's
// entry point, or at the first potential leaf its search found (the search's trail).
#include "beamtrace/query.hpp"
#include "mlrta/entry_point.hpp"
#include "mlrta/mlrta_impl.hpp"

namespace beamtrace::mlrta {

// The packet from `ep` (nothing when the search proved that no ray of the packet hits anything:
// ep.misses). `trail`, if given, is that of the entry-point search that found `ep` for a beam holding
// the packet's rays. With kCount, the traversal's counters grow.
template <bool kOcclusion, bool kCount>
void trace_packet(const Mlrta::Impl& m, const Packet16& packet, const EntryPoint& ep, PacketHits16* hits,
                  std::uint32_t* occluded, QueryCounters* counters, const SearchTrail* trail = nullptr);

// Packets packets[0 .. n) of one tile together (kdtree::trace_packets_together) from `ep`, as
// trace_packet for each.
template <bool kOcclusion, bool kCount>
void trace_packets_together(const Mlrta::Impl& m, const Packet16* const* packets, int n, const EntryPoint& ep,
                            PacketHits16* const* hits, std::uint32_t* const* occluded, QueryCounters* counters,
                            const SearchTrail* trail = nullptr);

// The root of the tree as an entry point.
EntryPoint root_entry(const Mlrta::Impl& m);

}  // namespace beamtrace::mlrta
