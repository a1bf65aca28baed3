// Ray streams: many packets traced PSF by PSF and, within a PSF, tile by tile. Pass 1 looks every
// ray up (SIMD) and counts the rays of each PSF; pass 2 copies each ray, with its place in the
// input and its first tile, into its PSF's bin; each bin is then ordered by first tile (a stable
// counting sort by column, then by row), cut into packets again and traced, and the answers put
// back where the rays came from. Rays of one tile follow one another, and the tiles of a PSF are
// visited in the order their blocks lie in memory, so a PSF is read front to back, not at random.
// The packets of a bin are traced as a pipeline (packet_start.hpp): the lookups of packet g + 2 and
// the first blocks of packet g + 2 are requested from memory while packet g walks.
#include <algorithm>
#include <utility>
#include <vector>

#include "common/query_runner.hpp"
#include "vlf/query/field_query.hpp"
#include "vlf/stream/packet_start.hpp"
#include "vlf/stream/tile_ray_stream.hpp"

namespace beamtrace {
namespace {

// A ray's PSF and first tile in one word (PSF < 2^12, tile < 2^20: l <= 2049, n <= 1024).
constexpr std::uint32_t kTileBits = 20;

struct BinnedRay {
    Ray ray;
    std::uint32_t slot;  // packet * 16 + lane in the input
    std::uint32_t tile;  // row * n + column of the tile where its segment starts
};

// Stable counting sort of in by key(ray) < buckets into out.
template <class Key>
void counting_sort(std::span<const BinnedRay> in, BinnedRay* out, std::uint32_t buckets,
                   std::vector<std::uint32_t>& next, Key&& key) {
    next.assign(std::size_t(buckets) + 1, 0);
    for (const BinnedRay& r : in) ++next[key(r) + 1];
    for (std::uint32_t b = 0; b < buckets; ++b) next[b + 1] += next[b];
    for (const BinnedRay& r : in) out[next[key(r)]++] = r;
}

// Up to 16 rays as a packet, with their start (lookups, first tiles) and where they came from: a
// packet of the input as it is (in order), or one made of binned rays (`own`).
struct Group {
    const Packet16* packet = nullptr;
    Packet16 own;
    std::uint32_t slots[16];
    std::size_t index = 0;  // in order: the input packet's place
    vlf::PacketStart start;
};

// Calls walk(group) for `groups` groups, filled by fill(g, group) (packet, slots), as a pipeline:
// while group g walks, the first blocks of group g + 1 and g + 2 and the tile entries of group
// g + 3 are on their way from memory (see packet_start.hpp).
template <class Fill, class Walk>
void pipeline(const VisibilityField::Impl& f, std::size_t groups, Fill&& fill, Walk&& walk) {
    constexpr std::size_t kAhead = 3;
    Group ring[kAhead + 1];
    auto at = [&](std::size_t g) -> Group& { return ring[g % (kAhead + 1)]; };
    auto begin = [&](std::size_t g) {
        fill(g, at(g));
        vlf::start_packet(f, *at(g).packet, at(g).start);
    };
    for (std::size_t g = 0; g < groups && g < kAhead; ++g) begin(g);
    if (groups > 0) vlf::prefetch_first_blocks(at(0).start);
    if (groups > 1) vlf::prefetch_first_blocks(at(1).start);
    for (std::size_t g = 0; g < groups; ++g) {
        if (g + 3 < groups) begin(g + 3);
        if (g + 2 < groups) vlf::prefetch_first_blocks(at(g + 2).start);
        walk(at(g));
        // Between walks no tile is held (groups ahead hold PSFs and prefetched addresses only).
        if ((g & 3) == 3) f.quiescent();
    }
}

// The rays of one bin, 16 at a time.
template <class Walk>
void trace_bin(const VisibilityField::Impl& f, std::span<const BinnedRay> rays, Walk&& walk) {
    pipeline(
        f, (rays.size() + 15) / 16,
        [&](std::size_t g, Group& q) {
            const std::size_t b = g * 16;
            const int count = int(std::min<std::size_t>(16, rays.size() - b));
            q.own.active = count == 16 ? 0xFFFFu : (1u << count) - 1u;
            for (int k = 0; k < 16; ++k) {
                const BinnedRay& r = rays[b + std::size_t(k < count ? k : 0)];
                q.own.set_ray(k, r.ray);
                q.slots[k] = r.slot;
            }
            q.packet = &q.own;
        },
        walk);
}

// The packets as given (not copied: a group points at its packet, whose place is its index).
template <class Walk>
void in_order(const VisibilityField::Impl& f, std::span<const Packet16> packets, Walk&& walk) {
    pipeline(
        f, packets.size(),
        [&](std::size_t g, Group& q) {
            q.packet = &packets[g];
            q.index = g;
            for (int k = 0; k < 16; ++k) q.slots[k] = std::uint32_t(g * 16 + std::size_t(k));
        },
        walk);
}

// Calls walk(group) for every ray of the packets, grouped by PSF and ordered by first tile, except
// the rays that `tiles` (occlusion streams) takes: those whose segment stays in its first tile.
template <class Walk>
void binned(const VisibilityField::Impl& f, std::span<const Packet16> packets, Walk&& walk,
            vlf::TileRayBins* tiles = nullptr, VlfMode mode = VlfMode::exact) {
    const std::size_t psfs = f.psfs.size();
    const auto n = std::uint32_t(f.grid.n);
    // The rays left to walk, as (slot, PSF << kTileBits | tile), in input order (a stream of one-tile
    // rays leaves none: no array over the whole stream).
    std::vector<std::pair<std::uint32_t, std::uint32_t>> rest;
    std::vector<std::size_t> first(psfs + 1, 0);
    vlf::PacketLookup lookup;
    if (tiles) tiles->begin(psfs, n, packets.size() * 16);
    for (std::size_t p = 0; p < packets.size(); ++p) {
        vlf::lookup_packet(f, packets[p], lookup, tiles != nullptr);
        const std::uint32_t taken = tiles ? tiles->take(f, packets[p], lookup, std::uint32_t(p * 16), mode) : 0u;
        for (std::uint32_t m = lookup.valid & ~taken; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            const std::uint32_t tile = std::uint32_t(lookup.row[i]) * n + std::uint32_t(lookup.column[i]);
            rest.emplace_back(std::uint32_t(p * 16 + std::size_t(i)), (lookup.psf[i] << kTileBits) | tile);
            ++first[lookup.psf[i] + 1];
        }
    }
    for (std::size_t i = 0; i < psfs; ++i) first[i + 1] += first[i];
    std::vector<BinnedRay> rays(first[psfs]);
    {
        std::vector<std::size_t> next(first.begin(), first.end() - 1);
        for (const auto& [slot, b] : rest)
            rays[next[b >> kTileBits]++] =
                BinnedRay{packets[slot / 16].ray(int(slot % 16)), slot, b & ((1u << kTileBits) - 1u)};
    }
    rest = {};
    std::vector<BinnedRay> scratch;
    std::vector<std::uint32_t> counts;
    for (std::size_t i = 0; i < psfs; ++i) {
        const std::span<BinnedRay> bin(rays.data() + first[i], first[i + 1] - first[i]);
        if (bin.empty()) continue;
        if (bin.size() > 16) {
            scratch.resize(bin.size());
            counting_sort(bin, scratch.data(), n, counts, [n](const BinnedRay& r) { return r.tile % n; });
            counting_sort(scratch, bin.data(), n, counts, [n](const BinnedRay& r) { return r.tile / n; });
        }
        f.quiescent();
        trace_bin(f, bin, walk);
    }
}

}  // namespace

void VisibilityField::intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits, VlfMode mode,
                                VlfOrder order) const {
    check_query("VisibilityField::intersect", packets.size(), hits.size(), QueryOptions{});
    const Impl& f = *impl_;
    const auto guard = f.reading();
    if (order == VlfOrder::automatic) order = VlfOrder::input;  // camera packets
    auto closest = [&](const Group& g, int i) {
        return vlf::walk_field<false, false>(f, *g.start.psf[i], g.start.lookup.ray(i),
                                             g.start.lookup.watertight(i, *g.packet), mode, nullptr);
    };
    if (order == VlfOrder::input) {
        // Each packet's answers written once, all 16 lanes (no clearing pass over the output).
        return in_order(f, packets, [&](const Group& g) {
            PacketHits16& out = hits[g.index];
            for (int i = 0; i < 16; ++i) out.set_hit(i, ((g.start.lookup.valid >> i) & 1u) ? closest(g, i) : Hit{});
        });
    }
    for (PacketHits16& h : hits)
        for (int i = 0; i < 16; ++i) h.set_hit(i, Hit{});
    // Under a memory budget, binned in parts whose bins take at most the budget's stream share.
    const std::size_t part = f.stream_packets();
    for (std::size_t first = 0; first < packets.size(); first += part) {
        const std::size_t count = std::min(part, packets.size() - first);
        binned(f, packets.subspan(first, count), [&](const Group& g) {
            for (std::uint32_t m = g.start.lookup.valid; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                hits[first + g.slots[i] / 16].set_hit(int(g.slots[i] % 16), closest(g, i));
            }
        });
    }
}

void VisibilityField::occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded, VlfMode mode,
                               VlfOrder order) const {
    check_query("VisibilityField::occluded", packets.size(), occluded.size(), QueryOptions{});
    if (order == VlfOrder::automatic) order = VlfOrder::psf;  // incoherent secondary rays
    for (std::uint32_t& bits : occluded) bits = 0;
    const Impl& f = *impl_;
    const auto guard = f.reading();
    auto walk = [&](const Group& g) {
        for (std::uint32_t m = g.start.lookup.valid; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            if (vlf::walk_field<true, false>(f, *g.start.psf[i], g.start.lookup.ray(i),
                                             g.start.lookup.watertight(i, *g.packet), mode, nullptr)
                    .hit())
                occluded[g.slots[i] / 16] |= 1u << (g.slots[i] % 16);
        }
    };
    if (order == VlfOrder::input) return in_order(f, packets, walk);
    // Binned: rays whose segment stays in one tile in batches (tile_ray_stream.hpp), the others walk.
    // Under a memory budget, in parts whose bins take at most the budget's stream share.
    vlf::TileRayLease lease(f);
    const std::size_t part = f.stream_packets();
    for (std::size_t first = 0; first < packets.size(); first += part) {
        const std::size_t count = std::min(part, packets.size() - first);
        const std::span<std::uint32_t> out = occluded.subspan(first, count);
        auto walk_part = [&](const Group& g) {
            for (std::uint32_t m = g.start.lookup.valid; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                if (vlf::walk_field<true, false>(f, *g.start.psf[i], g.start.lookup.ray(i),
                                                 g.start.lookup.watertight(i, *g.packet), mode, nullptr)
                        .hit())
                    out[g.slots[i] / 16] |= 1u << (g.slots[i] % 16);
            }
        };
        binned(f, packets.subspan(first, count), walk_part, &lease.bins(), mode);
        lease.bins().trace(f, out);
    }
}

}  // namespace beamtrace
