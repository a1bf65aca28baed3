// Ray streams: many packets traced PSF by PSF. Pass 1 looks every ray up (SIMD) and counts the
// rays of each PSF; pass 2 copies each ray, with its place in the input, into its PSF's bin; the
// bins are then cut into packets again, traced, and the answers put back where the rays came from.
// Within a bin the rays keep their input order, so rays from neighbouring pixels stay together and
// meet neighbouring tiles.
#include <vector>

#include "vlf/field_query.hpp"
#include "vlf/packet_start.hpp"

namespace beamtrace {
namespace {

constexpr std::uint16_t kNoPsf = 0xFFFF;

struct BinnedRay {
    Ray ray;
    std::uint32_t slot;  // packet * 16 + lane in the input
};

// Calls trace(packet, slots, count) for packets of up to 16 rays of one PSF each.
template <class Trace>
void binned(const VisibilityField::Impl& f, std::span<const Packet16> packets, Trace&& trace) {
    const std::size_t psfs = f.psfs.size();
    std::vector<std::uint16_t> psf_of(packets.size() * 16, kNoPsf);
    std::vector<std::size_t> first(psfs + 1, 0);
    vlf::PacketLookup lookup;
    for (std::size_t p = 0; p < packets.size(); ++p) {
        vlf::lookup_packet(f, packets[p], lookup);
        for (std::uint32_t m = lookup.valid; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            psf_of[p * 16 + std::size_t(i)] = std::uint16_t(lookup.psf[i]);
            ++first[lookup.psf[i] + 1];
        }
    }
    for (std::size_t i = 0; i < psfs; ++i) first[i + 1] += first[i];
    std::vector<BinnedRay> rays(first[psfs]);
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    for (std::size_t slot = 0; slot < psf_of.size(); ++slot)
        if (psf_of[slot] != kNoPsf) rays[next[psf_of[slot]]++] = BinnedRay{packets[slot / 16].ray(int(slot % 16)), std::uint32_t(slot)};
    Packet16 packet;
    std::uint32_t slots[16];
    for (std::size_t i = 0; i < psfs; ++i)
        for (std::size_t b = first[i]; b < first[i + 1]; b += 16) {
            const int count = int(std::min<std::size_t>(16, first[i + 1] - b));
            packet.active = (1u << count) - 1u;
            for (int k = 0; k < 16; ++k) {
                const BinnedRay& r = rays[b + std::size_t(k < count ? k : 0)];
                packet.set_ray(k, r.ray);
                slots[k] = r.slot;
            }
            trace(packet, slots);
        }
}

}  // namespace

void VisibilityField::intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits, VlfMode mode) const {
    for (PacketHits16& h : hits)
        for (int i = 0; i < 16; ++i) h.set_hit(i, Hit{});
    const Impl& f = *impl_;
    binned(f, packets, [&](const Packet16& packet, const std::uint32_t* slots) {
        vlf::PacketStart s;
        vlf::start_packet(f, packet, s);
        for (std::uint32_t m = s.lookup.valid; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            const Hit h = vlf::walk_field<false, false>(f, *s.psf[i], s.lookup.ray(i), s.lookup.watertight(i, packet),
                                                        mode, nullptr);
            hits[slots[i] / 16].set_hit(int(slots[i] % 16), h);
        }
    });
}

void VisibilityField::occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded, VlfMode mode) const {
    for (std::uint32_t& bits : occluded) bits = 0;
    const Impl& f = *impl_;
    binned(f, packets, [&](const Packet16& packet, const std::uint32_t* slots) {
        vlf::PacketStart s;
        vlf::start_packet(f, packet, s);
        for (std::uint32_t m = s.lookup.valid; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            if (vlf::walk_field<true, false>(f, *s.psf[i], s.lookup.ray(i), s.lookup.watertight(i, packet), mode, nullptr)
                    .hit())
                occluded[slots[i] / 16] |= 1u << (slots[i] % 16);
        }
    });
}

}  // namespace beamtrace
