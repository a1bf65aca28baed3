#pragma once
// Entry-point (EP) search with the bifurcation stack (MLRTA section 4.1, steps 1-3 and the
// termination conditions (4)): the deepest node from which every ray of a beam can start.
#include <cstdint>

#include "mlrta/beam.hpp"
#include "mlrta/entry_point.hpp"
#include "mlrta/mlrta_impl.hpp"

namespace beamtrace::mlrta {

// Depth first from `start` with frustum culling; bifurcation nodes (both children possible) are
// stacked until the first leaf with potential intersections, the candidate. Then each stacked node,
// from the top, has its other subtree searched for another such leaf; if one exists, that node
// becomes the candidate. The search ends when the stack is empty, or at once when the first
// candidate is a flat leaf completely covered by triangles that every ray of the beam must cross
// within its segment (all rays end there). A beam with no potential leaf at all gets `misses`.
// `steps` counts the nodes visited. settings.ep_search chooses the paper's order (bifurcation
// stack) or the top-down walk that returns the same node with fewer steps.
//
// `trail`, if given, is the trail of a search from `start` for a beam that holds this one (the
// parent tile's): the walk then starts at that search's first potential leaf. `out`, if given,
// receives this search's trail, for searches of parts of this beam from the returned entry point.
EntryPoint entry_point_search(const Mlrta::Impl& m, const Beam& beam, const EntryPoint& start, std::uint64_t& steps,
                              const SearchTrail* trail = nullptr, SearchTrail* out = nullptr);

}  // namespace beamtrace::mlrta
