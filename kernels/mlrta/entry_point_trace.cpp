#include "mlrta/entry_point_trace.hpp"

namespace beamtrace::mlrta {

namespace {

// The resume point of `trail` (null when there is none).
const kdtree::TraversalResume* resume_of(const SearchTrail* trail, kdtree::TraversalResume& resume) {
    if (!trail || !trail->valid) return nullptr;
    for (int k = 0; k < 3; ++k) resume.sign[k] = trail->sign[k];
    resume.first = trail->first;
    resume.path = trail->bif.at;
    resume.count = trail->count;
    return &resume;
}

// What a packet reports when the search proved that none of its rays hits anything.
template <bool kOcclusion, bool kCount>
void answer_miss(PacketHits16* hits, std::uint32_t* occluded, QueryCounters* counters) {
    if constexpr (kOcclusion)
        *occluded = 0;
    else
        for (int i = 0; i < 16; ++i) hits->set_hit(i, Hit{});
    if constexpr (kCount) ++counters->packets;
}

}  // namespace

template <bool kOcclusion, bool kCount>
void trace_packet(const Mlrta::Impl& m, const Packet16& packet, const EntryPoint& ep, PacketHits16* hits,
                  std::uint32_t* occluded, QueryCounters* counters, const SearchTrail* trail) {
    if (ep.misses) return answer_miss<kOcclusion, kCount>(hits, occluded, counters);
    kdtree::TraversalResume resume;
    kdtree::trace_packet<kOcclusion, kCount>(m.packets, packet,
                                             kdtree::TraversalStart{{ep.node, ep.box}, resume_of(trail, resume)}, hits,
                                             occluded, counters);
}

template <bool kOcclusion, bool kCount>
void trace_packets_together(const Mlrta::Impl& m, const Packet16* const* packets, int n, const EntryPoint& ep,
                            PacketHits16* const* hits, std::uint32_t* const* occluded, QueryCounters* counters,
                            const SearchTrail* trail) {
    if (ep.misses) {
        for (int p = 0; p < n; ++p)
            answer_miss<kOcclusion, kCount>(kOcclusion ? nullptr : hits[p], kOcclusion ? occluded[p] : nullptr,
                                            counters);
        return;
    }
    kdtree::TraversalResume resume;
    kdtree::trace_packets_together<kOcclusion, kCount>(
        m.packets, packets, n, kdtree::TraversalStart{{ep.node, ep.box}, resume_of(trail, resume)}, hits, occluded,
        counters);
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

#define BEAMTRACE_TRACE_FROM_ENTRY(kOcclusion, kCount)                                                           \
    template void trace_packets_together<kOcclusion, kCount>(const Mlrta::Impl&, const Packet16* const*, int,     \
                                                             const EntryPoint&, PacketHits16* const*,             \
                                                             std::uint32_t* const*, QueryCounters*, const SearchTrail*);
BEAMTRACE_TRACE_FROM_ENTRY(false, false)
BEAMTRACE_TRACE_FROM_ENTRY(false, true)
BEAMTRACE_TRACE_FROM_ENTRY(true, false)
BEAMTRACE_TRACE_FROM_ENTRY(true, true)
#undef BEAMTRACE_TRACE_FROM_ENTRY

}  // namespace beamtrace::mlrta
