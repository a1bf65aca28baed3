#pragma once
// The groups of a sorted stream traced by what suits each (docs/streams.md, step 6): pencils through
// a shared point as packets (through the wide BVH or by interval traversal), a cell's runs of one
// origin by the masked group traversal, loose rays in direction-ordered groups or alone.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include <immintrin.h>

#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "bvh/wide_bvh_packet.hpp"
#include "common/morton.hpp"
#include "kdtree/packet/packet_traversal.hpp"
#include "kdtree/ray_traversal.hpp"
#include "mlrta/shadow_reversal.hpp"
#include "stream/group_traversal.hpp"
#include "stream/ray_groups.hpp"
#include "stream/ray_keys.hpp"
#include "stream/sorted_stream.hpp"
#include "stream/wide_bvh_use.hpp"

namespace beamtrace::stream {

// Pencil packets traced together (4: 64 rays, as MLRTA's blocks of 4x4 packets share one interval
// traversal; docs/mlrta.md "Packets traced together").
constexpr std::size_t kPencilBlock = 4;

// The rays of a group as a packet (lanes 0 .. count; the others the ray (0, 0, 0) + t (0, 0, 1),
// t in [0, 0]): four rays at a time, each ray's two halves (origin and tnear, direction and tfar)
// transposed into the packet's rows.
// ray(j) gives the j-th ray (j < count).
template <class RayAt>
Packet16 packet_of(RayAt ray, std::uint32_t count) {
    static_assert(sizeof(Ray) == 8 * sizeof(float));
    alignas(16) static constexpr float kUnused[8] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f};
    Packet16 p;
    for (std::uint32_t b = 0; b < 16; b += 4) {
        __m128 o[4], d[4];
        for (std::uint32_t j = 0; j < 4; ++j) {
            const float* r = b + j < count ? reinterpret_cast<const float*>(&ray(b + j)) : kUnused;
            o[j] = _mm_loadu_ps(r);
            d[j] = _mm_loadu_ps(r + 4);
        }
        _MM_TRANSPOSE4_PS(o[0], o[1], o[2], o[3]);
        _MM_TRANSPOSE4_PS(d[0], d[1], d[2], d[3]);
        _mm_store_ps(p.org_x + b, o[0]);
        _mm_store_ps(p.org_y + b, o[1]);
        _mm_store_ps(p.org_z + b, o[2]);
        _mm_store_ps(p.tnear + b, o[3]);
        _mm_store_ps(p.dir_x + b, d[0]);
        _mm_store_ps(p.dir_y + b, d[1]);
        _mm_store_ps(p.dir_z + b, d[2]);
        _mm_store_ps(p.tfar + b, d[3]);
    }
    p.active = count >= 16 ? 0xFFFFu : (1u << count) - 1u;
    return p;
}

inline Packet16 packet_of(const Ray* rays, std::uint32_t count) {
    return packet_of([rays](std::uint32_t j) -> const Ray& { return rays[j]; }, count);
}

// The cell of a direction among 4^bits (bits <= 4) for ordering loose rays: the octahedral
// projection (as octahedral_code, but with one reciprocal and no branches; the exact code is not
// needed here, neighbouring cells only).
[[gnu::always_inline]] inline std::uint32_t loose_direction_cell(const Float3& d, int bits) {
    const float r = 1.0f / (std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z));
    const float u = d.x * r, v = d.y * r;
    const bool lower = d.z < 0.0f;
    const float fu = lower ? std::copysign(1.0f - std::fabs(v), u) : u;
    const float fv = lower ? std::copysign(1.0f - std::fabs(u), v) : v;
    const float cells = float(1 << bits);
    const auto cell = [&](float x) {
        const float q = (x * 0.5f + 0.5f) * cells;
        if (!(q > 0.0f)) return 0u;  // NaN too
        return q < cells - 1.0f ? std::uint32_t(q) : std::uint32_t(cells - 1.0f);
    };
    const std::uint32_t cu = cell(fu), cv = cell(fv);
    return (spread_bits_2(cu) | (spread_bits_2(cv) << 1)) & ((1u << (2 * bits)) - 1u);
}

// Loose rays (StreamTrace::loose) are grouped within windows of sorted neighbours (near origins)
// by the octahedral cell of their direction. A window is a 256th of the call's rays, between
// kMinLooseWindow and kMaxLooseWindow: about a 256th of the surfaces the rays start from, whatever
// their number, so a denser stream gets finer direction cells in the same region (as many as leave
// about 16 rays a cell).
constexpr std::uint32_t kMinLooseWindow = 256, kMaxLooseWindow = 4096;
// The most direction cells a window uses: 4^4 (loose_window below, for kMaxLooseWindow).
constexpr std::uint32_t kMaxLooseCells = 1u << (2 * ((std::countr_zero(kMaxLooseWindow) - 4) / 2));

struct LooseWindow {
    std::uint32_t rays;
    int direction_bits;
};

inline LooseWindow loose_window(std::size_t call_rays) {
    std::uint32_t w = kMinLooseWindow;
    while (w < kMaxLooseWindow && std::size_t(w) * 2 * 256 <= call_rays) w *= 2;
    // 4^bits cells of about 16 rays: bits = log4(w / 16), rounded down.
    return {w, (std::countr_zero(w) - 4) / 2};
}

template <bool kOcclusion, class Out>
class StreamTrace {
public:
    StreamTrace(const KdTree::Impl& kd, const KdExperimental& x, const SortedStream& sorted,
                std::uint32_t min_group_rays, bool group_loose_rays, bool bvh_pencils, WideBvhUse wide_bvh, Out* out)
        : kd_(kd),
          bvh_(wide_bvh),
          context_{kd, kd.packet_tables(), x.triangle_culling},
          root_(kdtree::root_start(kd)),
          rays_(sorted.rays.data()),
          sorted_(sorted),
          min_group_rays_(min_group_rays),
          group_loose_rays_(group_loose_rays),
          bvh_pencils_(bvh_pencils),
          window_(loose_window(sorted.rays.size())),
          out_(out),
          tolerance_(mlrta::reversal_tolerance(kd.bounds)) {}

    template <bool kCount>
    void groups(std::size_t begin, std::size_t end, QueryCounters* c) const {
        LooseRange pending;
        for (std::size_t g = begin; g < end;) {
            const RayGroup& group = sorted_.groups[g];
            switch (group.kind) {
                case RayGroup::Kind::pencil:
                    g = pencils<kCount>(g, end, c);
                    continue;
                case RayGroup::Kind::cell:
                    cell<kCount>(group, pending, c);
                    break;
                case RayGroup::Kind::single:
                    defer<kCount>(pending, group.begin, group.begin + group.count, c);
                    break;
                case RayGroup::Kind::no_segment:
                    for (std::uint32_t k = group.begin; k < group.begin + group.count; ++k) write(k, Hit{});
                    break;
            }
            ++g;
        }
        loose<kCount>(pending.begin, pending.end, c);
    }

private:
    // Sorted positions of loose rays not traced yet (the short runs of neighbouring groups, merged).
    struct LooseRange {
        std::uint32_t begin = 0, end = 0;
    };

    // [b, e) joins `pending` when it follows it; otherwise pending is traced and [b, e) takes its place.
    template <bool kCount>
    void defer(LooseRange& pending, std::uint32_t b, std::uint32_t e, QueryCounters* c) const {
        if (b == e) return;
        if (pending.end == b && pending.begin != pending.end) {
            pending.end = e;
            return;
        }
        loose<kCount>(pending.begin, pending.end, c);
        pending = {b, e};
    }

    // Pencil groups from `first` (up to kPencilBlock of them through one point, neighbours in
    // direction: the sort's order) as packets traced together by one interval traversal (the
    // kd-tree's trace_packets_together: it goes packet by packet when they do not travel together).
    // Occlusion packets are traced from their light when they end at one (MLRTA section 6). Returns
    // the group after the block.
    template <bool kCount>
    std::size_t pencils(std::size_t first, std::size_t end, QueryCounters* c) const {
        const std::uint32_t point = sorted_.sorted_keys[sorted_.groups[first].begin] >> kPointShift;
        std::size_t last = first + 1;
        while (last < end && last - first < kPencilBlock && sorted_.groups[last].kind == RayGroup::Kind::pencil &&
               (sorted_.sorted_keys[sorted_.groups[last].begin] >> kPointShift) == point)
            ++last;
        const int n = int(last - first);
        if constexpr (kCount)
            for (std::size_t k = first; k < last; ++k) {
                ++c->stream.pencil_packets;
                c->stream.pencil_rays += sorted_.groups[k].count;
            }
        if constexpr (kOcclusion) {
            if (bvh_.bvh && bvh_pencils_) {
                // Occlusion pencils through the wide BVH, a packet at a time (bvh::occluded_packet:
                // the packet's bounds from the rays' far ends, where they meet).
                for (std::size_t k = first; k < last; ++k) {
                    const RayGroup& g = sorted_.groups[k];
                    const std::uint32_t bits = bvh::occluded_packet(*bvh_.bvh, packet_of(rays_ + g.begin, g.count),
                                                                    bvh_.kernels->isa, kCount ? c : nullptr);
                    write_lanes([&](std::uint32_t i) { return g.begin + i; }, g.count, nullptr, bits);
                }
                return last;
            }
        }
        Packet16 packets[kPencilBlock];
        const Packet16* traced[kPencilBlock] = {};
        PacketHits16 hits[kPencilBlock];
        PacketHits16* hits_of[kPencilBlock] = {};
        std::uint32_t bits[kPencilBlock] = {};
        std::uint32_t* bits_of[kPencilBlock] = {};
        for (int k = 0; k < n; ++k) {
            const RayGroup& g = sorted_.groups[first + std::size_t(k)];
            const Packet16 p = packet_of(rays_ + g.begin, g.count);
            if (!kOcclusion || !mlrta::reverse_for_occlusion(p, tolerance_, packets[k])) packets[k] = p;
            traced[k] = &packets[k];
            hits_of[k] = &hits[k];
            bits_of[k] = &bits[k];
        }
        kdtree::trace_packets_together<kOcclusion, kCount>(context_, traced, n, root_, hits_of, bits_of, c);
        for (int k = 0; k < n; ++k) {
            const RayGroup& g = sorted_.groups[first + std::size_t(k)];
            write_lanes([&](std::uint32_t i) { return g.begin + i; }, g.count, &hits[k], bits[k]);
        }
        return last;
    }

    // The rays of sorted positions [begin, end) one by one (through the wide BVH when there is one).
    template <bool kCount>
    void singles(std::uint32_t begin, std::uint32_t end, QueryCounters* c) const {
        if (bvh_.bvh) {
            bvh_.template trace_range<kOcclusion, kCount>(
                begin, end, [this](std::size_t k) -> const Ray& { return rays_[k]; }, out_, c);
            return;
        }
        const kdtree::CornerRows rows = context_.tables.rows();
        for (std::uint32_t k = begin; k < end; ++k)
            write(k, kdtree::traverse_ray_in_rows<kOcclusion, kCount>(kd_, rays_[k], rows.at, rows.stride, c));
    }

    // Rays of sorted positions [begin, end) in no group: in equal parts of at most 16 neighbours by
    // the masked group traversal (they share the steps from the root down to their origins' cells),
    // or one by one (fewer than min_group_rays_, or group_loose_rays_ off).
    template <bool kCount>
    void loose(std::uint32_t begin, std::uint32_t end, QueryCounters* c) const {
        const std::uint32_t count = end - begin;
        if (bvh_.bvh || !group_loose_rays_ || count < min_group_rays_) {
            if constexpr (kCount) c->stream.single_rays += count;
            singles<kCount>(begin, end, c);
            return;
        }
        // Windows of neighbours in the sort's order, each put in order of the octahedral cell of the
        // rays' directions (a stable counting sort), then cut into groups.
        const std::uint32_t bins = 1u << (2 * window_.direction_bits);
        std::uint32_t positions[kMaxLooseWindow];
        std::uint8_t bin[kMaxLooseWindow];
        for (std::uint32_t w = begin; w < end; w += window_.rays) {
            const std::uint32_t n = std::min(window_.rays, end - w);
            if (n <= 16) {
                for (std::uint32_t i = 0; i < n; ++i) positions[i] = w + i;
            } else {
                std::uint32_t first[kMaxLooseCells + 1] = {};
                for (std::uint32_t i = 0; i < n; ++i) {
                    bin[i] = std::uint8_t(loose_direction_cell(rays_[w + i].dir, window_.direction_bits));
                    ++first[bin[i] + 1];
                }
                for (std::uint32_t b = 0; b < bins; ++b) first[b + 1] += first[b];
                for (std::uint32_t i = 0; i < n; ++i) positions[first[bin[i]]++] = w + i;
            }
            const std::uint32_t parts = (n + 15) / 16;
            for (std::uint32_t p = 0; p < parts; ++p) {
                const std::uint32_t b = n * p / parts, e = n * (p + 1) / parts;
                if constexpr (kCount) {
                    ++c->stream.loose_groups;
                    c->stream.loose_group_rays += e - b;
                }
                group<kCount>([&](std::uint32_t j) { return positions[b + j]; }, e - b, c);
            }
        }
    }

    // The rays of sorted positions at(0) .. at(n - 1), n <= 16, by the masked group traversal.
    template <bool kCount, class At>
    void group(At at, std::uint32_t n, QueryCounters* c) const {
        const Packet16 packet = packet_of([&](std::uint32_t j) -> const Ray& { return rays_[at(j)]; }, n);
        PacketHits16 hits;
        std::uint32_t bits = 0;
        trace_group<kOcclusion, kCount>(kd_, packet, &hits, &bits, c);
        write_lanes([&](std::uint32_t i) { return at(i); }, n, &hits, bits);
    }

    // A cell's rays, each origin's next to each other (the sort's origin hash; two origins that share
    // a hash may interleave): runs of one origin, bit for bit, of at least min_group_rays_ rays as
    // groups of at most 16 (masked group traversal), shorter runs deferred as loose rays.
    template <bool kCount>
    void cell(const RayGroup& g, LooseRange& pending, QueryCounters* c) const {
        const std::uint32_t end = g.begin + g.count;
        std::uint32_t loose_begin = g.begin;  // the short runs since the last group
        for (std::uint32_t k = g.begin; k < end;) {
            const Ray& first = rays_[k];
            std::uint32_t run_end = k + 1;
            while (run_end < end && same_origin(rays_[run_end], first)) ++run_end;
            const std::uint32_t count = run_end - k;
            if (count < min_group_rays_) {
                k = run_end;
                continue;
            }
            defer<kCount>(pending, loose_begin, k, c);
            loose_begin = run_end;
            // Equal parts of at most 16 (a run of 17 makes 9 + 8, not 16 + 1).
            const std::uint32_t parts = (count + 15) / 16;
            for (std::uint32_t p = 0; p < parts; ++p) {
                const std::uint32_t b = k + count * p / parts, e = k + count * (p + 1) / parts;
                if constexpr (kCount) {
                    ++c->stream.origin_groups;
                    c->stream.origin_group_rays += e - b;
                }
                group<kCount>([b](std::uint32_t j) { return b + j; }, e - b, c);
            }
            k = run_end;
        }
        defer<kCount>(pending, loose_begin, end, c);
    }

    static bool same_origin(const Ray& a, const Ray& b) {
        return std::bit_cast<std::uint32_t>(a.org.x) == std::bit_cast<std::uint32_t>(b.org.x) &&
               std::bit_cast<std::uint32_t>(a.org.y) == std::bit_cast<std::uint32_t>(b.org.y) &&
               std::bit_cast<std::uint32_t>(a.org.z) == std::bit_cast<std::uint32_t>(b.org.z);
    }

    // The answer of the ray at sorted position `position`.
    void write(std::uint32_t position, const Hit& h) const { store_answer<kOcclusion>(out_[position], h); }

    // Lanes 0 .. count - 1 of a packet's answers to the sorted positions index(i).
    template <class Index>
    void write_lanes(Index index, std::uint32_t count, const PacketHits16* hits, std::uint32_t bits) const {
        for (std::uint32_t i = 0; i < count; ++i) {
            if constexpr (kOcclusion)
                out_[index(i)] = std::uint8_t((bits >> i) & 1u);
            else
                out_[index(i)] = hits->hit(int(i));
        }
    }

    const KdTree::Impl& kd_;
    WideBvhUse bvh_;  // bvh null: single rays by the kd-tree
    kdtree::PacketTraversalContext context_;
    kdtree::TraversalStart root_;
    const Ray* rays_;  // in sorted order
    const SortedStream& sorted_;
    std::uint32_t min_group_rays_;
    bool group_loose_rays_;
    bool bvh_pencils_;  // occlusion pencils through the wide BVH (StreamSettings::bvh_pencils)
    LooseWindow window_;
    Out* out_;  // the answers by sorted position (trace_stream writes them out in input order)
    double tolerance_;
};

}  // namespace beamtrace::stream
