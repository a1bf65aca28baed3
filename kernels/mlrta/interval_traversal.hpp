#pragma once
// Interval traversal of 4x4 packets (MLRTA section 4.3, the "XP search"): from an entry point, one
// interval [t_cell_min, t_cell_max] for the whole packet, the packet's [t_plane_min, t_plane_max]
// per split, near / far / both exactly as the paper's pseudo-code, with a stack. At leaves: the
// slab-pair test (2) against the leaf box, mailboxing, optional triangle-box culling, then the 16
// rays against each triangle with the watertight SIMD kernel; early exit when every active ray
// has a hit nearer than the cells left on the stack.
#include "beamtrace/mlrta.hpp"
#include "mlrta/entry_point.hpp"
#include "mlrta/mlrta_impl.hpp"

namespace beamtrace::mlrta {

// A whole packet from `ep`: the lanes are grouped by sign octant and each group is traced by
// interval traversal; lanes with a zero direction component, groups of one or two rays, groups
// whose origins lie more than 1% of the scene diagonal apart and groups whose directions spread
// more than about 3 degrees go to the single-ray kd-tree traversal.
//
// `trail`, if given, is that of the entry-point search that found `ep` for a beam holding the
// packet's rays: a group of the beam's signs then starts at the search's first potential leaf, with
// the other children of the bifurcations on its path on the stack (every leaf before it in the
// depth-first order holds nothing the packet can hit).
template <bool kOcclusion, bool kCount>
void trace_packet(const Mlrta::Impl& m, const Packet16& packet, const EntryPoint& ep, PacketHits16* hits,
                  std::uint32_t* occluded, MlrtaCounters* counters, const SearchTrail* trail = nullptr);

// The root of the tree as an entry point.
EntryPoint root_entry(const Mlrta::Impl& m);

}  // namespace beamtrace::mlrta
