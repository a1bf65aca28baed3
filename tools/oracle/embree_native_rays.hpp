#pragma once
// Rays prebuilt in Embree's own layouts, so that a timed region can hold Embree's query calls and
// nothing else: this is how Embree's manual has an application trace (rays written once into
// RTCRayHit / RTCRayHit16 / RTCRay..., then rtcIntersect* over them), and how the benchmark's Embree
// engines (embree1, embree16, embree-stream) give the anchor every ratio is measured against.
//
// Made (untimed) from the 4x4 packets of a ray set; each active ray goes through the oracle's rules
// (embree_segment.hpp): rays Embree cannot take report no hit and are never occluded, as in the
// oracle. reset() (untimed) restores what a query overwrites, trace() is the timed part, hits() /
// occluded() (untimed) give the answers per slot (packet * 16 + lane).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/ray.hpp"
#include "oracle/embree_oracle.hpp"

namespace beamtrace::oracle {

// How the rays are handed to Embree.
enum class EmbreeLayout {
    single,    // one RTCRayHit / RTCRay per active ray, rtcIntersect1 / rtcOccluded1 each (embree1)
    packet16,  // one RTCRayHit16 / RTCRay16 per 4x4 packet with its valid mask, rtcIntersect16 / rtcOccluded16
               // (embree16)
    stream,    // the active rays as one array of RTCRayHit / RTCRay, rtcIntersect1M / rtcOccluded1M (embree-stream)
};

// The RTCIntersectContext flag of a query. Embree's manual: coherent for rays that travel together
// (primary camera rays), incoherent (the default of rtcInitIntersectContext) for scattered ones.
enum class EmbreeContextFlag { coherent, incoherent };
const char* to_string(EmbreeContextFlag flag);

class EmbreeNativeRays {
public:
    // Converts the active rays of the packets into the layout, for closest-hit queries
    // (closest_hit) or occlusion queries. The target (the oracle, or an EmbreeAnimation) must outlive
    // this object. slot_time: each slot's time (packets * 16 values; Embree's ray time, what motion
    // blur reads), or empty for time 0.
    EmbreeNativeRays(const EmbreeTarget& target, EmbreeLayout layout, std::span<const Packet16> packets,
                     bool closest_hit, std::span<const float> slot_time = {});
    ~EmbreeNativeRays();
    EmbreeNativeRays(const EmbreeNativeRays&) = delete;
    EmbreeNativeRays& operator=(const EmbreeNativeRays&) = delete;

    // The pieces trace() can be split into across threads: packets (packet16), blocks of
    // kStreamBlock rays (stream) or rays (single).
    std::size_t units() const;
    static constexpr std::size_t kStreamBlock = 256;

    // Restores every ray's tfar (and, for closest hits, geomID) from the values it was made with.
    void reset();
    // The timed part: Embree's query calls over the units [begin, end), with one context per call.
    // Units of different calls may run concurrently (each ray belongs to one unit).
    void trace(EmbreeContextFlag flag, std::size_t begin, std::size_t end);

    // Answers of the last trace per slot of the packets given at construction (packets * 16
    // entries; inactive slots: no hit, not occluded).
    void hits(std::vector<Hit>& out) const;
    void occluded(std::vector<std::uint8_t>& out) const;
    // The same into the caller's span of exactly packets * 16 entries (e.g. a part of a larger set's
    // answers); throws beamtrace::Error for another size.
    void hits(std::span<Hit> out) const;
    void occluded(std::span<std::uint8_t> out) const;

    // Bytes of the prebuilt layout (rays, masks, the copy reset() restores from, slot maps).
    std::size_t bytes() const;
    std::size_t rays() const;  // rays handed to Embree (active rays Embree can take)

private:
    struct Layout;
    std::unique_ptr<Layout> layout_;
};

}  // namespace beamtrace::oracle
