// The kd-tree's query contract (query.hpp): single rays and spans of rays by single-ray traversal,
// spans of packets by interval traversal from the root (kdtree/packet).
#include "common/query_runner.hpp"
#include "kdtree/packet/packet_traversal.hpp"
#include "kdtree/ray_traversal.hpp"

namespace beamtrace {

using kdtree::traverse_ray;

namespace {

constexpr std::size_t kRayGrain = 1024, kPacketGrain = 16;

template <bool kOcclusion, class Out>
void trace_rays(const KdTree::Impl& kd, std::span<const Ray> rays, Out* out, const QueryOptions& options) {
    run_query(rays.size(), options, kRayGrain, [&](std::size_t b, std::size_t e, QueryCounters* c) {
        if (c) {
            for (std::size_t i = b; i < e; ++i) {
                const Hit h = traverse_ray<kOcclusion, true>(kd, rays[i], c);
                if constexpr (kOcclusion)
                    out[i] = h.hit();
                else
                    out[i] = h;
            }
        } else {
            for (std::size_t i = b; i < e; ++i) {
                const Hit h = traverse_ray<kOcclusion, false>(kd, rays[i], nullptr);
                if constexpr (kOcclusion)
                    out[i] = h.hit();
                else
                    out[i] = h;
            }
        }
    });
}

template <bool kOcclusion>
void trace_packets(const KdTree::Impl& kd, const KdExperimental& x, std::span<const Packet16> packets,
                   PacketHits16* hits, std::uint32_t* bits, const QueryOptions& options) {
    const kdtree::PacketTraversalContext context{kd, kd.packet_tables(), x.triangle_culling};
    const kdtree::TraversalStart root = kdtree::root_start(kd);
    run_query(packets.size(), options, kPacketGrain, [&](std::size_t b, std::size_t e, QueryCounters* c) {
        for (std::size_t p = b; p < e; ++p) {
            PacketHits16* h = kOcclusion ? nullptr : hits + p;
            std::uint32_t* o = kOcclusion ? bits + p : nullptr;
            if (c)
                kdtree::trace_packet<kOcclusion, true>(context, packets[p], root, h, o, c);
            else
                kdtree::trace_packet<kOcclusion, false>(context, packets[p], root, h, o, nullptr);
        }
    });
}

}  // namespace

Hit KdTree::intersect(const Ray& ray) const { return kdtree::intersect_one(*impl_, ray); }
bool KdTree::occluded(const Ray& ray) const { return kdtree::occluded_one(*impl_, ray); }

void KdTree::intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options) const {
    check_query("KdTree::intersect", rays.size(), hits.size(), options);
    trace_rays<false>(*impl_, rays, hits.data(), options);
}

void KdTree::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded, const QueryOptions& options) const {
    check_query("KdTree::occluded", rays.size(), occluded.size(), options);
    trace_rays<true>(*impl_, rays, occluded.data(), options);
}

void KdTree::intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                       const QueryOptions& options) const {
    check_query("KdTree::intersect", packets.size(), hits.size(), options);
    trace_packets<false>(*impl_, experimental_, packets, hits.data(), nullptr, options);
}

void KdTree::occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                      const QueryOptions& options) const {
    check_query("KdTree::occluded", packets.size(), occluded.size(), options);
    trace_packets<true>(*impl_, experimental_, packets, nullptr, occluded.data(), options);
}

KdTree KdTree::with_experimental(const KdExperimental& experimental) const {
    KdTree t(impl_);
    t.experimental_ = experimental;
    return t;
}

std::size_t KdTree::packet_table_bytes() const { return impl_->packet_table_bytes(); }
void KdTree::prepare_packet_queries() const { impl_->packet_tables(); }

}  // namespace beamtrace
