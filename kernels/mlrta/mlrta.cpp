// The Mlrta object: tables built once, tiles run (in parallel with TBB), single packets from the root.
#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "beamtrace/error.hpp"
#include "mlrta/covered_leaves.hpp"
#include "mlrta/interval_traversal.hpp"
#include "mlrta/tile_splitter.hpp"

namespace beamtrace {

void MlrtaSettings::validate() const {
    auto fail = [](const std::string& what) { throw Error("MLRTA settings: " + what); };
    if (initial_tile < 4 || initial_tile % 4 != 0 || initial_tile > 4096)
        fail("initial_tile must be a multiple of 4 between 4 and 4096 pixels");
    if (min_tile < 4 || min_tile % 4 != 0 || min_tile > initial_tile)
        fail("min_tile must be a multiple of 4 between 4 and initial_tile");
    if (split_factor != 4 && split_factor != 16) fail("split_factor must be 4 or 16");
}

MlrtaCounters& MlrtaCounters::operator+=(const MlrtaCounters& o) {
    packets += o.packets;
    ep_steps += o.ep_steps;
    xp_steps += o.xp_steps;
    triangle_tests += o.triangle_tests;
    tiles += o.tiles;
    divergent_tiles += o.divergent_tiles;
    single_rays += o.single_rays;
    blocked_tiles += o.blocked_tiles;
    return *this;
}

Mlrta::Mlrta(const KdTree& tree, const MlrtaSettings& settings) {
    settings.validate();
    auto impl = std::make_shared<Impl>(tree, settings);
    impl->subtree_nodes = mlrta::subtree_sizes(tree.impl());
    impl->covered_leaf = mlrta::covered_flat_leaves(tree.impl());
    impl->geometry_boxes = mlrta::leaf_geometry_boxes(tree.impl());
    impl_ = std::move(impl);
}

const MlrtaSettings& Mlrta::settings() const { return impl_->settings; }
const KdTree& Mlrta::tree() const { return impl_->tree; }
std::size_t Mlrta::memory_bytes() const {
    return impl_->subtree_nodes.size() * sizeof(std::uint32_t) + impl_->covered_leaf.size() +
           impl_->geometry_boxes.size() * sizeof(Box);
}

namespace {

void check_grid(const PacketGrid& grid) {
    if (grid.columns < 0 || grid.rows < 0 || (grid.packets == nullptr && grid.columns * grid.rows > 0))
        throw Error("MLRTA: the packet grid is inconsistent (negative size or no packets)");
}

template <bool kOcclusion>
void run_tiles(const Mlrta::Impl& m, const PacketGrid& grid, PacketHits16* hits, std::uint32_t* occluded, int threads,
               MlrtaCounters* counters, const TileObserver& observer) {
    check_grid(grid);
    if (threads < 1) throw Error("MLRTA: threads must be at least 1");
    const int side = std::max(1, m.settings.initial_tile / 4);
    const int tiles_x = (grid.columns + side - 1) / side, tiles_y = (grid.rows + side - 1) / side;
    const TileObserver* obs = observer ? &observer : nullptr;
    auto run = [&](int tx0, int tx1, int ty0, int ty1, MlrtaCounters* c) {
        if (c) {
            mlrta::TileSplitter<kOcclusion, true> splitter(m, grid, hits, occluded, c, obs);
            for (int ty = ty0; ty < ty1; ++ty)
                for (int tx = tx0; tx < tx1; ++tx) splitter.trace_initial_tile(tx * side, ty * side);
        } else {
            mlrta::TileSplitter<kOcclusion, false> splitter(m, grid, hits, occluded, nullptr, obs);
            for (int ty = ty0; ty < ty1; ++ty)
                for (int tx = tx0; tx < tx1; ++tx) splitter.trace_initial_tile(tx * side, ty * side);
        }
    };
    if (threads == 1) {
        run(0, tiles_x, 0, tiles_y, counters);
        return;
    }
    tbb::combinable<MlrtaCounters> per_thread;
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range2d<int>(0, tiles_y, 1, 0, tiles_x, 1),
                          [&](const tbb::blocked_range2d<int>& r) {
                              run(r.cols().begin(), r.cols().end(), r.rows().begin(), r.rows().end(),
                                  counters ? &per_thread.local() : nullptr);
                          });
    });
    if (counters) per_thread.combine_each([&](const MlrtaCounters& c) { *counters += c; });
}

}  // namespace

void Mlrta::intersect(const PacketGrid& grid, PacketHits16* hits, int threads, MlrtaCounters* counters,
                      const TileObserver& observer) const {
    run_tiles<false>(*impl_, grid, hits, nullptr, threads, counters, observer);
}

void Mlrta::occluded(const PacketGrid& grid, std::uint32_t* occluded, int threads, MlrtaCounters* counters) const {
    run_tiles<true>(*impl_, grid, nullptr, occluded, threads, counters, {});
}

void Mlrta::intersect_packet(const Packet16& packet, PacketHits16& hits, MlrtaCounters* counters) const {
    const mlrta::EntryPoint root = mlrta::root_entry(*impl_);
    if (counters) mlrta::trace_packet<false, true>(*impl_, packet, root, &hits, nullptr, counters);
    else mlrta::trace_packet<false, false>(*impl_, packet, root, &hits, nullptr, nullptr);
}

std::uint32_t Mlrta::occluded_packet(const Packet16& packet, MlrtaCounters* counters) const {
    const mlrta::EntryPoint root = mlrta::root_entry(*impl_);
    std::uint32_t bits = 0;
    if (counters) mlrta::trace_packet<true, true>(*impl_, packet, root, nullptr, &bits, counters);
    else mlrta::trace_packet<true, false>(*impl_, packet, root, nullptr, &bits, nullptr);
    return bits;
}

Ray reversed(const Ray& r) {
    Ray out;
    out.org = r.org + r.dir * r.tfar;
    out.dir = r.dir * -1.0f;
    out.tnear = 0.0f;
    out.tfar = r.tfar - r.tnear;
    return out;
}

}  // namespace beamtrace
