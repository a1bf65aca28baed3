#include "mlrta/entry_point_trace.hpp"

namespace beamtrace::mlrta {

template <bool kOcclusion, bool kCount>
void trace_packet(const Mlrta::Impl& m, const Packet16& packet, const EntryPoint& ep, PacketHits16* hits,
                  std::uint32_t* occluded, QueryCounters* counters, const SearchTrail* trail) {
    if (ep.misses) {
        if constexpr (kOcclusion)
            *occluded = 0;
        else
            for (int i = 0; i < 16; ++i) hits->set_hit(i, Hit{});
        if constexpr (kCount) ++counters->packets;
        return;
    }
    kdtree::TraversalResume resume;
    const kdtree::TraversalResume* from = nullptr;
    if (trail && trail->valid) {
        for (int k = 0; k < 3; ++k) resume.sign[k] = trail->sign[k];
        resume.first = trail->first;
        resume.path = trail->bif.at;
        resume.count = trail->count;
        from = &resume;
    }
    kdtree::trace_packet<kOcclusion, kCount>(m.packets, packet, kdtree::TraversalStart{{ep.node, ep.box}, from}, hits,
                                             occluded, counters);
}

EntryPoint root_entry(const Mlrta::Impl& m) {
    EntryPoint ep;
    ep.node = 0;
    ep.box = m.kd().bounds;
    return ep;
}

#define BEAMTRACE_TRACE_FROM_ENTRY(kOcclusion, kCount)                                                     \
    template void trace_packet<kOcclusion, kCount>(const Mlrta::Impl&, const Packet16&, const EntryPoint&, \
                                                   PacketHits16*, std::uint32_t*, QueryCounters*, const SearchTrail*);
BEAMTRACE_TRACE_FROM_ENTRY(false, false)
BEAMTRACE_TRACE_FROM_ENTRY(false, true)
BEAMTRACE_TRACE_FROM_ENTRY(true, false)
BEAMTRACE_TRACE_FROM_ENTRY(true, true)
#undef BEAMTRACE_TRACE_FROM_ENTRY

}  // namespace beamtrace::mlrta
