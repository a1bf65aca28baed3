#include "oracle/embree_native_rays.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <optional>
#include <string>

#include "beamtrace/error.hpp"
#include "oracle/embree_ray_fill.hpp"

namespace beamtrace::oracle {

const char* to_string(EmbreeContextFlag flag) {
    return flag == EmbreeContextFlag::coherent ? "coherent" : "incoherent";
}

namespace {

struct alignas(64) ValidMask16 {
    int lane[16];
};

}  // namespace

struct EmbreeNativeRays::Layout {
    const EmbreeTarget* target = nullptr;
    RTCScene scene = nullptr;
    EmbreeLayout kind = EmbreeLayout::single;
    bool closest = true;
    std::size_t slots = 0;

    // packet16: the packets with at least one ray Embree takes, and where each came from.
    std::vector<RTCRayHit16> hit16;
    std::vector<RTCRay16> ray16;
    std::vector<ValidMask16> valid;
    std::vector<std::uint32_t> packet_of;
    // single, stream: the rays Embree takes, and their slots.
    std::vector<RTCRayHit> hit1;
    std::vector<RTCRay> ray1;
    std::vector<std::uint32_t> slot_of;
    // Per lane (packet16) or per ray (single, stream): tfar as made (what reset() restores) and, for
    // closest hits, how Embree's t maps back to the caller's.
    std::vector<float> tfar0, shift, t_scale;

    std::size_t rays = 0;

    void keep_conversion(const EmbreeSegment& s) {
        tfar0.push_back(s.tfar);
        if (closest) {
            shift.push_back(s.shift);
            t_scale.push_back(s.t_scale);
        }
    }
    float caller_t(std::size_t k, float t) const { return t / t_scale[k] + shift[k]; }
};

EmbreeNativeRays::EmbreeNativeRays(const EmbreeTarget& target, EmbreeLayout layout, std::span<const Packet16> packets,
                                   bool closest_hit, std::span<const float> slot_time)
    : layout_(std::make_unique<Layout>()) {
    Layout& m = *layout_;
    m.target = &target;
    m.scene = target.native_scene();
    if (!slot_time.empty() && slot_time.size() != packets.size() * 16)
        throw Error("embree rays: " + std::to_string(slot_time.size()) + " slot times for " +
                    std::to_string(packets.size() * 16) + " slots");
    const auto time_of = [&](std::size_t slot) { return slot_time.empty() ? 0.0f : slot_time[slot]; };
    m.kind = layout;
    m.closest = closest_hit;
    m.slots = packets.size() * 16;
    if (m.scene == nullptr) throw Error("embree rays: the target has no scene");

    // Room for every active ray (rays Embree refuses are rare): the arrays grow once, never by doubling.
    std::size_t active_rays = 0, active_packets = 0;
    for (const Packet16& packet : packets) {
        active_rays += std::size_t(__builtin_popcount(packet.active & 0xFFFFu));
        active_packets += (packet.active & 0xFFFFu) != 0;
    }
    const std::size_t per_ray = layout == EmbreeLayout::packet16 ? active_packets * 16 : active_rays;
    m.tfar0.reserve(per_ray);
    if (m.closest) {
        m.shift.reserve(per_ray);
        m.t_scale.reserve(per_ray);
    }
    if (layout == EmbreeLayout::packet16) {
        m.packet_of.reserve(active_packets);
        m.valid.reserve(active_packets);
        if (m.closest)
            m.hit16.reserve(active_packets);
        else
            m.ray16.reserve(active_packets);
    } else {
        m.slot_of.reserve(active_rays);
        if (m.closest)
            m.hit1.reserve(active_rays);
        else
            m.ray1.reserve(active_rays);
    }

    if (layout == EmbreeLayout::packet16) {
        for (std::size_t p = 0; p < packets.size(); ++p) {
            std::optional<EmbreeSegment> lane[16];
            bool any = false;
            for (int i = 0; i < 16; ++i) {
                if ((packets[p].active >> i) & 1u) lane[i] = to_embree(packets[p].ray(i));
                any = any || lane[i].has_value();
            }
            if (!any) continue;
            if (p > 0xFFFFFFFFu) throw Error("embree rays: more than 2^32 packets");
            m.packet_of.push_back(std::uint32_t(p));
            ValidMask16& v = m.valid.emplace_back();
            if (m.closest)
                m.hit16.emplace_back();
            else
                m.ray16.emplace_back();
            for (int i = 0; i < 16; ++i) {
                v.lane[i] = lane[i] ? -1 : 0;
                m.rays += lane[i].has_value();
                const EmbreeSegment& s = lane[i] ? *lane[i] : kIdleLane;
                const float time = time_of(p * 16 + std::size_t(i));
                if (m.closest)
                    fill_lane(m.hit16.back().ray, i, s, time);
                else
                    fill_lane(m.ray16.back(), i, s, time);
                m.keep_conversion(s);
            }
        }
    } else {
        for (std::size_t p = 0; p < packets.size(); ++p)
            for (std::uint32_t bits = packets[p].active & 0xFFFFu; bits; bits &= bits - 1) {
                const int i = __builtin_ctz(bits);
                const std::optional<EmbreeSegment> s = to_embree(packets[p].ray(i));
                if (!s) continue;
                const std::size_t slot = p * 16 + std::size_t(i);
                if (slot > 0xFFFFFFFFu) throw Error("embree rays: more than 2^32 ray slots");
                m.slot_of.push_back(std::uint32_t(slot));
                if (m.closest)
                    fill_ray(m.hit1.emplace_back().ray, *s, time_of(slot));
                else
                    fill_ray(m.ray1.emplace_back(), *s, time_of(slot));
                m.keep_conversion(*s);
                ++m.rays;
            }
        if (layout == EmbreeLayout::stream && m.slot_of.size() > 0xFFFFFFFFu)
            throw Error("embree rays: a stream of more than 2^32 rays");
    }
    reset();
}

EmbreeNativeRays::~EmbreeNativeRays() = default;

std::size_t EmbreeNativeRays::units() const {
    const Layout& m = *layout_;
    switch (m.kind) {
        case EmbreeLayout::packet16:
            return m.packet_of.size();
        case EmbreeLayout::stream:
            return (m.slot_of.size() + kStreamBlock - 1) / kStreamBlock;
        case EmbreeLayout::single:
            return m.slot_of.size();
    }
    return 0;
}

void EmbreeNativeRays::reset() {
    Layout& m = *layout_;
    if (m.kind == EmbreeLayout::packet16) {
        for (std::size_t k = 0; k < m.packet_of.size(); ++k) {
            const float* t = m.tfar0.data() + k * 16;
            if (m.closest) {
                RTCRayHit16& rh = m.hit16[k];
                std::copy(t, t + 16, rh.ray.tfar);
                std::fill(rh.hit.geomID, rh.hit.geomID + 16, RTC_INVALID_GEOMETRY_ID);
                std::fill(rh.hit.primID, rh.hit.primID + 16, RTC_INVALID_GEOMETRY_ID);
                std::fill(rh.hit.instID[0], rh.hit.instID[0] + 16, RTC_INVALID_GEOMETRY_ID);
            } else {
                std::copy(t, t + 16, m.ray16[k].tfar);
            }
        }
        return;
    }
    for (std::size_t k = 0; k < m.slot_of.size(); ++k) {
        if (m.closest) {
            RTCRayHit& rh = m.hit1[k];
            rh.ray.tfar = m.tfar0[k];
            rh.hit.geomID = rh.hit.primID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        } else {
            m.ray1[k].tfar = m.tfar0[k];
        }
    }
}

void EmbreeNativeRays::trace(EmbreeContextFlag flag, std::size_t begin, std::size_t end) {
    Layout& m = *layout_;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = flag == EmbreeContextFlag::coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT
                                                        : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    switch (m.kind) {
        case EmbreeLayout::packet16:
            if (m.closest)
                for (std::size_t k = begin; k < end; ++k)
                    rtcIntersect16(m.valid[k].lane, m.scene, &context, &m.hit16[k]);
            else
                for (std::size_t k = begin; k < end; ++k)
                    rtcOccluded16(m.valid[k].lane, m.scene, &context, &m.ray16[k]);
            break;
        case EmbreeLayout::single:
            if (m.closest)
                for (std::size_t k = begin; k < end; ++k) rtcIntersect1(m.scene, &context, &m.hit1[k]);
            else
                for (std::size_t k = begin; k < end; ++k) rtcOccluded1(m.scene, &context, &m.ray1[k]);
            break;
        case EmbreeLayout::stream: {
            const std::size_t first = begin * kStreamBlock, last = std::min(end * kStreamBlock, m.slot_of.size());
            if (first >= last) break;
            const auto count = static_cast<unsigned>(last - first);
            if (m.closest)
                rtcIntersect1M(m.scene, &context, &m.hit1[first], count, sizeof(RTCRayHit));
            else
                rtcOccluded1M(m.scene, &context, &m.ray1[first], count, sizeof(RTCRay));
            break;
        }
    }
}

void EmbreeNativeRays::hits(std::vector<Hit>& out) const {
    out.resize(layout_->slots);
    hits(std::span<Hit>(out));
}

void EmbreeNativeRays::occluded(std::vector<std::uint8_t>& out) const {
    out.resize(layout_->slots);
    occluded(std::span<std::uint8_t>(out));
}

void EmbreeNativeRays::hits(std::span<Hit> out) const {
    const Layout& m = *layout_;
    if (!m.closest) throw Error("embree rays: made for occlusion queries, asked for closest hits");
    if (out.size() != m.slots)
        throw Error("embree rays: " + std::to_string(out.size()) + " answer slots for " + std::to_string(m.slots));
    std::fill(out.begin(), out.end(), Hit{});
    if (m.kind == EmbreeLayout::packet16) {
        for (std::size_t k = 0; k < m.packet_of.size(); ++k) {
            const RTCRayHit16& rh = m.hit16[k];
            for (int i = 0; i < 16; ++i) {
                if (m.valid[k].lane[i] == 0 || rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
                out[std::size_t(m.packet_of[k]) * 16 + std::size_t(i)] =
                    Hit{m.caller_t(k * 16 + std::size_t(i), rh.ray.tfar[i]), m.target->triangle_id(rh.hit.geomID[i], rh.hit.primID[i]),
                        rh.hit.u[i], rh.hit.v[i]};
            }
        }
        return;
    }
    for (std::size_t k = 0; k < m.slot_of.size(); ++k) {
        const RTCRayHit& rh = m.hit1[k];
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        out[m.slot_of[k]] = Hit{m.caller_t(k, rh.ray.tfar), m.target->triangle_id(rh.hit.geomID, rh.hit.primID), rh.hit.u, rh.hit.v};
    }
}

void EmbreeNativeRays::occluded(std::span<std::uint8_t> out) const {
    const Layout& m = *layout_;
    if (m.closest) throw Error("embree rays: made for closest-hit queries, asked for occlusion");
    if (out.size() != m.slots)
        throw Error("embree rays: " + std::to_string(out.size()) + " answer slots for " + std::to_string(m.slots));
    std::fill(out.begin(), out.end(), std::uint8_t{0});
    // Embree marks an occluded ray with tfar = -inf.
    if (m.kind == EmbreeLayout::packet16) {
        for (std::size_t k = 0; k < m.packet_of.size(); ++k)
            for (int i = 0; i < 16; ++i)
                if (m.valid[k].lane[i] != 0 && m.ray16[k].tfar[i] == -kInfinity)
                    out[std::size_t(m.packet_of[k]) * 16 + std::size_t(i)] = 1;
        return;
    }
    for (std::size_t k = 0; k < m.slot_of.size(); ++k)
        if (m.ray1[k].tfar == -kInfinity) out[m.slot_of[k]] = 1;
}

std::size_t EmbreeNativeRays::bytes() const {
    const Layout& m = *layout_;
    return m.hit16.size() * sizeof(RTCRayHit16) + m.ray16.size() * sizeof(RTCRay16) +
           m.valid.size() * sizeof(ValidMask16) + m.packet_of.size() * sizeof(std::uint32_t) +
           m.hit1.size() * sizeof(RTCRayHit) + m.ray1.size() * sizeof(RTCRay) +
           m.slot_of.size() * sizeof(std::uint32_t) +
           (m.tfar0.size() + m.shift.size() + m.t_scale.size()) * sizeof(float);
}

std::size_t EmbreeNativeRays::rays() const { return layout_->rays; }

}  // namespace beamtrace::oracle
