// The Mlrta object: tables built once; images traced by tiles (in parallel with TBB); other rays by
// the tree's packet traversal from the root; occlusion rays reversed towards their light first.
#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "beamtrace/error.hpp"
#include "bvh/wide_bvh_packet.hpp"
#include "common/query_runner.hpp"
#include "common/ray_packing.hpp"
#include "kdtree/ray_traversal.hpp"
#include "mlrta/covered_leaves.hpp"
#include "mlrta/entry_point_trace.hpp"
#include "mlrta/shadow_reversal.hpp"
#include "mlrta/tile_tracer.hpp"

namespace beamtrace {

void MlrtaSettings::validate() const {
    auto fail = [](const std::string& what) { throw Error("MLRTA settings: " + what); };
    if (initial_tile < 4 || initial_tile % 4 != 0 || initial_tile > 4096)
        fail("initial_tile must be a multiple of 4 between 4 and 4096 pixels");
    if (min_tile < 4 || min_tile % 4 != 0 || min_tile > initial_tile)
        fail("min_tile must be a multiple of 4 between 4 and initial_tile");
    if (split_factor != 4 && split_factor != 16) fail("split_factor must be 4 or 16");
    const int xp = experimental.xp_packets;
    if (xp != 1 && xp != 2 && xp != 4)
        fail("experimental.xp_packets must be 1, 2 or 4 (packets per side traced together)");
}

Mlrta::Impl::Impl(const KdTree& t, const MlrtaSettings& s)
    : tree(t),
      settings(s),
      packets{detail::Access::impl(t), detail::Access::impl(t).packet_tables(), s.experimental.triangle_culling} {}

Mlrta::Mlrta(const KdTree& tree, const MlrtaSettings& settings) {
    settings.validate();
    auto impl = std::make_shared<Impl>(tree, settings);
    impl->subtree_nodes = mlrta::subtree_sizes(impl->kd());
    impl->covered_leaf = mlrta::covered_flat_leaves(impl->kd());
    impl_ = std::move(impl);
}

const bvh::WideBvh& Mlrta::Impl::wide_bvh() const {
    std::call_once(bvh_once, [this] {
        bvh = bvh::WideBvh::build(kd().scene);
        bvh_made.store(bvh.get(), std::memory_order_release);
    });
    return *bvh;
}

void Mlrta::prepare_occlusion() const {
    if (impl_->settings.experimental.shadow_bvh) impl_->wide_bvh();
}

const MlrtaSettings& Mlrta::settings() const { return impl_->settings; }
const KdTree& Mlrta::tree() const { return impl_->tree; }
std::size_t Mlrta::memory_bytes() const {
    const bvh::WideBvh* made = impl_->bvh_made.load(std::memory_order_acquire);  // only once built
    const std::size_t bvh_bytes = made ? made->stats.memory_bytes : 0;
    return impl_->subtree_nodes.size() * sizeof(std::uint32_t) + impl_->covered_leaf.size() +
           impl_->tree.packet_table_bytes() + bvh_bytes;
}

namespace {

void check_grid(const PacketGrid& grid, std::size_t answers, const QueryOptions& options, const char* what) {
    if (grid.columns < 0 || grid.rows < 0 || (grid.packets == nullptr && grid.columns * grid.rows > 0))
        throw Error(std::string(what) + ": the packet grid is inconsistent (negative size or no packets)");
    check_query(what, std::size_t(grid.columns) * std::size_t(grid.rows), answers, options);
}

// Occlusion packets through the wide BVH (MlrtaExperimental::shadow_bvh), packet by packet on the
// options' threads; counters: packets, packet_steps (nodes), leaves and triangle tests.
void occluded_through_bvh(const Mlrta::Impl& m, const Packet16* packets, std::size_t n, std::uint32_t* occluded,
                          const QueryOptions& options) {
    const bvh::WideBvh& b = m.wide_bvh();
    const Isa isa = m.kd().kernels->isa;
    run_query(n, options, 64, [&](std::size_t begin, std::size_t end, QueryCounters* c) {
        for (std::size_t k = begin; k < end; ++k) {
            if (k + 2 < end)
                for (std::size_t line = 0; line < sizeof(Packet16); line += 64)
                    __builtin_prefetch(reinterpret_cast<const char*>(&packets[k + 2]) + line);
            occluded[k] = bvh::occluded_packet(b, packets[k], isa, c);
        }
    });
}

template <bool kOcclusion>
void run_tiles(const Mlrta::Impl& m, const PacketGrid& grid, PacketHits16* hits, std::uint32_t* occluded,
               const QueryOptions& options, const TileObserver& observer) {
    const int side = std::max(1, m.settings.initial_tile / 4);
    const int tiles_x = (grid.columns + side - 1) / side, tiles_y = (grid.rows + side - 1) / side;
    const TileObserver* obs = observer ? &observer : nullptr;
    auto run = [&](int tx0, int tx1, int ty0, int ty1, QueryCounters* c) {
        auto tiles = [&](auto& tracer) {
            for (int ty = ty0; ty < ty1; ++ty)
                for (int tx = tx0; tx < tx1; ++tx) tracer.trace_initial_tile(tx * side, ty * side);
        };
        if (c) {
            mlrta::TileTracer<kOcclusion, true> tracer(m, grid, hits, occluded, c, obs, kOcclusion);
            tiles(tracer);
        } else {
            mlrta::TileTracer<kOcclusion, false> tracer(m, grid, hits, occluded, nullptr, obs, kOcclusion);
            tiles(tracer);
        }
    };
    if (options.threads == 1) {
        run(0, tiles_x, 0, tiles_y, options.counters);
        return;
    }
    tbb::combinable<QueryCounters> per_thread;
    tbb::task_arena arena(options.threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range2d<int>(0, tiles_y, 1, 0, tiles_x, 1),
                          [&](const tbb::blocked_range2d<int>& r) {
                              run(r.cols().begin(), r.cols().end(), r.rows().begin(), r.rows().end(),
                                  options.counters ? &per_thread.local() : nullptr);
                          });
    });
    if (options.counters) per_thread.combine_each([&](const QueryCounters& c) { *options.counters += c; });
}

// One packet from the root; occlusion packets reversed towards their light first when they can be.
template <bool kOcclusion, bool kCount>
void trace_from_root(const Mlrta::Impl& m, const mlrta::EntryPoint& root, double tolerance, const Packet16& packet,
                     PacketHits16* hits, std::uint32_t* occluded, QueryCounters* counters) {
    if constexpr (kOcclusion) {
        Packet16 traced;
        if (mlrta::reverse_for_occlusion(packet, tolerance, traced)) {
            mlrta::trace_packet<true, kCount>(m, traced, root, nullptr, occluded, counters);
            return;
        }
    }
    mlrta::trace_packet<kOcclusion, kCount>(m, packet, root, hits, occluded, counters);
}

template <bool kOcclusion>
void trace_packets(const Mlrta::Impl& m, std::span<const Packet16> packets, PacketHits16* hits, std::uint32_t* bits,
                   const QueryOptions& options) {
    const mlrta::EntryPoint root = mlrta::root_entry(m);
    const double tolerance = kOcclusion ? mlrta::reversal_tolerance(m.kd().scene.bounds()) : 0.0;
    run_query(packets.size(), options, 16, [&](std::size_t b, std::size_t e, QueryCounters* c) {
        for (std::size_t p = b; p < e; ++p) {
            PacketHits16* h = kOcclusion ? nullptr : hits + p;
            std::uint32_t* o = kOcclusion ? bits + p : nullptr;
            if (c)
                trace_from_root<kOcclusion, true>(m, root, tolerance, packets[p], h, o, c);
            else
                trace_from_root<kOcclusion, false>(m, root, tolerance, packets[p], h, o, nullptr);
        }
    });
}

// Rays 16 at a time as packets (the last one partial), answers back in input order.
template <bool kOcclusion, class Out>
void trace_rays(const Mlrta::Impl& m, std::span<const Ray> rays, Out* out, const QueryOptions& options) {
    const mlrta::EntryPoint root = mlrta::root_entry(m);
    const double tolerance = kOcclusion ? mlrta::reversal_tolerance(m.kd().scene.bounds()) : 0.0;
    const std::size_t packets = (rays.size() + 15) / 16;
    run_query(packets, options, 16, [&](std::size_t b, std::size_t e, QueryCounters* c) {
        for (std::size_t p = b; p < e; ++p) {
            Packet16 packet;
            const std::size_t first = p * 16, n = pack_rays(rays, first, packet);
            PacketHits16 hits;
            std::uint32_t bits = 0;
            if (c)
                trace_from_root<kOcclusion, true>(m, root, tolerance, packet, &hits, &bits, c);
            else
                trace_from_root<kOcclusion, false>(m, root, tolerance, packet, &hits, &bits, nullptr);
            for (std::size_t i = 0; i < n; ++i) {
                if constexpr (kOcclusion)
                    out[first + i] = std::uint8_t((bits >> i) & 1u);
                else
                    out[first + i] = hits.hit(int(i));
            }
        }
    });
}

}  // namespace

void Mlrta::intersect(const PacketGrid& grid, std::span<PacketHits16> hits, const QueryOptions& options,
                      const TileObserver& observer) const {
    check_grid(grid, hits.size(), options, "Mlrta::intersect");
    run_tiles<false>(*impl_, grid, hits.data(), nullptr, options, observer);
}

void Mlrta::occluded(const PacketGrid& grid, std::span<std::uint32_t> occluded, const QueryOptions& options) const {
    check_grid(grid, occluded.size(), options, "Mlrta::occluded");
    if (impl_->settings.experimental.shadow_bvh)
        return occluded_through_bvh(*impl_, grid.packets, std::size_t(grid.columns) * std::size_t(grid.rows),
                                    occluded.data(), options);
    run_tiles<true>(*impl_, grid, nullptr, occluded.data(), options, {});
}

Hit Mlrta::intersect(const Ray& ray) const { return kdtree::intersect_one(impl_->kd(), ray); }
bool Mlrta::occluded(const Ray& ray) const { return kdtree::occluded_one(impl_->kd(), ray); }

void Mlrta::intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options) const {
    check_query("Mlrta::intersect", rays.size(), hits.size(), options);
    trace_rays<false>(*impl_, rays, hits.data(), options);
}

void Mlrta::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded, const QueryOptions& options) const {
    check_query("Mlrta::occluded", rays.size(), occluded.size(), options);
    trace_rays<true>(*impl_, rays, occluded.data(), options);
}

void Mlrta::intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                      const QueryOptions& options) const {
    check_query("Mlrta::intersect", packets.size(), hits.size(), options);
    trace_packets<false>(*impl_, packets, hits.data(), nullptr, options);
}

void Mlrta::occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                     const QueryOptions& options) const {
    check_query("Mlrta::occluded", packets.size(), occluded.size(), options);
    if (impl_->settings.experimental.shadow_bvh)
        return occluded_through_bvh(*impl_, packets.data(), packets.size(), occluded.data(), options);
    trace_packets<true>(*impl_, packets, nullptr, occluded.data(), options);
}

}  // namespace beamtrace
