// The visibility field's query contract (query.hpp): the field's mode and order from its options,
// threads as contiguous streams, counted queries ray by ray with the single-ray walk.
#include <vector>

#include "common/query_runner.hpp"
#include "common/ray_packing.hpp"
#include "vlf/vlf_impl.hpp"

namespace beamtrace {

namespace {

// Rays are handed to the stream calls 16 at a time, this many packets per stream call.
constexpr std::size_t kChunk = 1024;

// The span of rays as packets of 16 (the last one partial), chunk by chunk, answers back in order.
template <bool kOcclusion, class Out, class TracePackets>
void rays_as_packets(std::span<const Ray> rays, Out* out, std::size_t begin, std::size_t end, TracePackets&& trace) {
    std::vector<Packet16> packets(kChunk);
    std::vector<PacketHits16> hits(kOcclusion ? 0 : kChunk);
    std::vector<std::uint32_t> bits(kOcclusion ? kChunk : 0);
    for (std::size_t first = begin; first < end; first += kChunk * 16) {
        const std::size_t n = std::min(end - first, kChunk * 16), count = (n + 15) / 16;
        for (std::size_t p = 0; p < count; ++p) pack_rays(rays.subspan(0, end), first + p * 16, packets[p]);
        if constexpr (kOcclusion)
            trace(std::span<const Packet16>(packets.data(), count), std::span(bits.data(), count));
        else
            trace(std::span<const Packet16>(packets.data(), count), std::span(hits.data(), count));
        for (std::size_t k = 0; k < n; ++k) {
            if constexpr (kOcclusion)
                out[first + k] = std::uint8_t((bits[k / 16] >> (k % 16)) & 1u);
            else
                out[first + k] = hits[k / 16].hit(int(k % 16));
        }
    }
}

}  // namespace

Hit VisibilityField::intersect(const Ray& ray) const { return intersect(ray, impl_->options.mode); }
bool VisibilityField::occluded(const Ray& ray) const { return occluded(ray, impl_->options.mode); }

void VisibilityField::intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options) const {
    check_query("VisibilityField::intersect", rays.size(), hits.size(), options);
    const VlfMode mode = impl_->options.mode;
    if (options.counters) {
        for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = intersect(rays[i], mode, *options.counters);
        return;
    }
    run_query_parts(rays.size(), options, [&](std::size_t b, std::size_t e) {
        rays_as_packets<false>(rays, hits.data(), b, e, [&](std::span<const Packet16> p, std::span<PacketHits16> h) {
            intersect(p, h, mode, impl_->options.order);
        });
    });
}

void VisibilityField::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                               const QueryOptions& options) const {
    check_query("VisibilityField::occluded", rays.size(), occluded.size(), options);
    const VlfMode mode = impl_->options.mode;
    if (options.counters) {
        for (std::size_t i = 0; i < rays.size(); ++i) occluded[i] = this->occluded(rays[i], mode, *options.counters);
        return;
    }
    run_query_parts(rays.size(), options, [&](std::size_t b, std::size_t e) {
        rays_as_packets<true>(rays, occluded.data(), b, e,
                              [&](std::span<const Packet16> p, std::span<std::uint32_t> o) {
                                  this->occluded(p, o, mode, impl_->options.order);
                              });
    });
}

void VisibilityField::intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                                const QueryOptions& options) const {
    check_query("VisibilityField::intersect", packets.size(), hits.size(), options);
    const VlfMode mode = impl_->options.mode;
    if (options.counters) {
        for (std::size_t p = 0; p < packets.size(); ++p)
            for (int i = 0; i < 16; ++i)
                hits[p].set_hit(
                    i, ((packets[p].active >> i) & 1u) ? intersect(packets[p].ray(i), mode, *options.counters) : Hit{});
        return;
    }
    run_query_parts(packets.size(), options, [&](std::size_t b, std::size_t e) {
        intersect(packets.subspan(b, e - b), hits.subspan(b, e - b), mode, impl_->options.order);
    });
}

void VisibilityField::occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                               const QueryOptions& options) const {
    check_query("VisibilityField::occluded", packets.size(), occluded.size(), options);
    const VlfMode mode = impl_->options.mode;
    if (options.counters) {
        for (std::size_t p = 0; p < packets.size(); ++p) {
            occluded[p] = 0;
            for (std::uint32_t m = packets[p].active & 0xFFFFu; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                if (this->occluded(packets[p].ray(i), mode, *options.counters)) occluded[p] |= 1u << i;
            }
        }
        return;
    }
    run_query_parts(packets.size(), options, [&](std::size_t b, std::size_t e) {
        this->occluded(packets.subspan(b, e - b), occluded.subspan(b, e - b), mode, impl_->options.order);
    });
}

}  // namespace beamtrace
