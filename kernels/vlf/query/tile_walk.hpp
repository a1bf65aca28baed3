#pragma once
// TileWalk: one ray through one PSF (sections 4 and 5). The ray's projected segment is walked
// across the tiles front to back (a DDA over tile boundaries in double: every tile the segment
// passes through; where it passes exactly through a corner it also visits one of the two tiles
// beside it for the length zero, and the padding of triangles covers the other). In each tile
// the depths of the segment's two ends give the first and last tile-BSP leaf, visited in order
// along the ray. A closest-hit walk stops as soon as its best hit is no farther than the end of the
// current leaf: everything nearer has been tested. Counting is a template parameter, so the counted
// path is the measured one.
//
// Mode fast (section 3.3's first description) visits only the tile where the segment starts, all
// its leaves between the segment's two depths.
#include <cstdint>
#include <limits>
#include <utility>

#include "beamtrace/vlf.hpp"
#include "common/triangle_kernels.hpp"
#include "common/triangle_reference.hpp"
#include "common/watertight_ray.hpp"
#include "vlf/directions/canonical_ray.hpp"
#include "vlf/query/mailbox.hpp"
#include "vlf/build/parallel_subfield.hpp"
#include "vlf/query/tile_footprint.hpp"
#include "vlf/vlf_kernels.hpp"

namespace beamtrace::vlf {

struct WalkContext {
    const TileGrid* grid = nullptr;
    const Triangle* triangles = nullptr;
    std::size_t triangle_count = 0;
    const std::uint32_t* order = nullptr;  // caller's id of each triangle: ties go to the smaller
    const TriangleKernels* kernels = nullptr;
    ScanFootprintsFn scan = nullptr;
    OccludeEntriesFn occlude = nullptr;
    ClosestEntriesFn closest = nullptr;  // nullptr: the walk's own leaf loop
};

// The ray's footprint (tile_footprint.hpp) over the part [t0, t1] of its segment.
inline std::uint32_t ray_footprint(const FootprintLattice& lattice, const CanonicalRay& cr, double t0, double t1) {
    const double xa = cr.ox + t0 * cr.dx, xb = cr.ox + t1 * cr.dx;
    const double ya = cr.oy + t0 * cr.dy, yb = cr.oy + t1 * cr.dy;
    return lattice.ray(xa < xb ? xa : xb, xa < xb ? xb : xa, ya < yb ? ya : yb, ya < yb ? yb : ya);
}

// Where the segment leaves its first tile (the end of the walk's first visit; t1 in mode fast).
template <bool kFast>
double first_tile_exit(const TileGrid& g, const CanonicalRay& cr) {
    if constexpr (kFast) return cr.t1;
    const double tx = cr.dx > 0.0   ? (g.edge(cr.column + 1) - cr.ox) * cr.inv_dx
                      : cr.dx < 0.0 ? (g.edge(cr.column) - cr.ox) * cr.inv_dx
                                    : std::numeric_limits<double>::infinity();
    const double ty = cr.dy > 0.0   ? (g.edge(cr.row + 1) - cr.oy) * cr.inv_dy
                      : cr.dy < 0.0 ? (g.edge(cr.row) - cr.oy) * cr.inv_dy
                                    : std::numeric_limits<double>::infinity();
    double exit = tx < ty ? tx : ty;
    exit = exit < cr.t1 ? exit : cr.t1;
    return exit > cr.t0 ? exit : cr.t0;
}

// Whether the segment lies in the tile where it starts (so a walk visits that tile alone).
template <bool kFast>
bool segment_in_first_tile(const TileGrid& g, const CanonicalRay& cr) {
    return kFast || first_tile_exit<false>(g, cr) >= cr.t1;
}

// Occlusion of a ray whose segment lies in its first tile (segment_in_first_tile): the visit of
// TileWalk as one fused kernel (entry_occlusion.hpp) over the leaves the segment spans, with the
// footprint of the whole segment. The same triangles as TileWalk tests; too_many (more than
// kFusedEntries entries, or more candidates than the kernel takes) leaves the ray to TileWalk.
inline constexpr std::uint32_t kFusedEntries = 64;
inline EntriesAnswer occlude_in_first_tile(const ParallelSubfield& psf, const WalkContext& ctx, const CanonicalRay& cr,
                                           const WatertightRay& ray, std::uint32_t& hit) {
    const TileGrid& g = *ctx.grid;
    const TileRef ref = psf.tile(std::uint32_t(cr.row) * std::uint32_t(g.n) + std::uint32_t(cr.column));
    if (ref.leaves == 0) return EntriesAnswer::clear;
    const TileBspView bsp = psf.view(ref);
    std::uint32_t j0 = 0, j1 = 0;
    if (ref.leaves > 1) {
        j0 = bsp.leaf(cr.oz + cr.t0 * cr.dz);
        j1 = bsp.leaf(cr.oz + cr.t1 * cr.dz);
        if (j0 > j1) std::swap(j0, j1);
    }
    const std::uint32_t first = bsp.begin(j0), count = bsp.end(j1) - first;
    // A long run (dense tiles: the room's desks) is better walked in chunks that stop at the first
    // hit than scanned whole before any test.
    if (count > kFusedEntries) return EntriesAnswer::too_many;
    const std::uint32_t footprint = ray_footprint(FootprintLattice::of_tile(g, cr.column, cr.row), cr, cr.t0, cr.t1);
    return ctx.occlude(ray, ctx.triangles, bsp.footprints() + first, bsp.ids() + first, count, footprint, j0 == j1,
                       &hit);
}

template <bool kOcclusion, bool kFast, bool kCount>
class TileWalk {
public:
    TileWalk(const ParallelSubfield& psf, const WalkContext& ctx, const WatertightRay& ray, QueryCounters* counters)
        : psf_(psf), ctx_(ctx), wray_(ray), counters_(counters) {}

    // Closest hit (or, for occlusion, any hit: best.triangle != kNoHit) along the segment of cr.
    Hit run(const CanonicalRay& cr) {
        const TileGrid& g = *ctx_.grid;
        int c = cr.column, r = cr.row;
        if constexpr (kFast) {
            visit(c, r, cr, cr.t0, cr.t1);
            return best_;
        }
        constexpr double kInf = std::numeric_limits<double>::infinity();
        const double inv_x = cr.inv_dx, inv_y = cr.inv_dy;
        auto next_x = [&] {
            return cr.dx > 0.0 ? (g.edge(c + 1) - cr.ox) * inv_x : cr.dx < 0.0 ? (g.edge(c) - cr.ox) * inv_x : kInf;
        };
        auto next_y = [&] {
            return cr.dy > 0.0 ? (g.edge(r + 1) - cr.oy) * inv_y : cr.dy < 0.0 ? (g.edge(r) - cr.oy) * inv_y : kInf;
        };
        double tx = next_x(), ty = next_y(), enter = cr.t0;
        for (;;) {
            double exit = tx < ty ? tx : ty;
            exit = exit < cr.t1 ? exit : cr.t1;
            exit = exit > enter ? exit : enter;
            if (visit(c, r, cr, enter, exit) || exit >= cr.t1) return best_;
            if (tx <= ty) {
                c += cr.dx > 0.0 ? 1 : -1;
                if (c < 0 || c >= g.n) return best_;
                tx = next_x();
            } else {
                r += cr.dy > 0.0 ? 1 : -1;
                if (r < 0 || r >= g.n) return best_;
                ty = next_y();
            }
            enter = exit;
        }
    }

private:
    // Tile (c, r) for the part [ta, tb] of the segment; true when the walk is finished (a hit no
    // farther than what has been covered, or any hit for occlusion).
    bool visit(int c, int r, const CanonicalRay& cr, double ta, double tb) {
        if constexpr (kCount) ++counters_->vlf.tiles;
        const TileRef ref = psf_.tile(std::uint32_t(r) * std::uint32_t(ctx_.grid->n) + std::uint32_t(c));
        if (ref.leaves == 0) return false;
        const TileBspView bsp = psf_.view(ref);
        const FootprintLattice lattice = FootprintLattice::of_tile(*ctx_.grid, c, r);
        auto footprint = [&](double t0, double t1) { return ray_footprint(lattice, cr, t0, t1); };
        if (ref.leaves == 1) {
            if constexpr (kOcclusion) return leaves(bsp, 0, 0, footprint(ta, tb));
            closest_in_leaf(bsp, 0, footprint(ta, tb));
            return double(best_.t) <= tb;
        }
        const std::uint32_t ja = bsp.leaf(cr.oz + ta * cr.dz), jb = bsp.leaf(cr.oz + tb * cr.dz);
        // Any hit ends an occlusion walk, so the order of its tests does not matter: the leaves
        // from ja to jb, stored one after the other, are scanned in one pass.
        if constexpr (kOcclusion) return leaves(bsp, ja < jb ? ja : jb, ja < jb ? jb : ja, footprint(ta, tb));
        // Closest hit: leaf by leaf, each with the footprint of the ray's part in it (a long,
        // slanted crossing of a dense tile covers much of the tile, its part in one leaf little).
        const bool forward = cr.dz > 0.0;
        double start = ta;
        for (std::uint32_t j = ja;; forward ? ++j : --j) {
            double end = tb;
            if (j != jb) end = (double(bsp.split(forward ? j : j - 1)) - cr.oz) * cr.inv_dz;
            end = end < start ? start : (end > tb ? tb : end);
            closest_in_leaf(bsp, j, footprint(start, end));
            if (double(best_.t) <= end) return true;
            if (j == jb) return false;
            start = end;
        }
    }

    // Closest hit: the untested triangles of leaf j whose footprint meets the ray's, by the fused
    // kernel (entry_closest_hit.hpp) where the instruction set has one and the ray still keeps its
    // tested ids in the short list, else by leaves(). The counting walks always take leaves().
    void closest_in_leaf(const TileBspView& bsp, std::uint32_t j, std::uint32_t ray) {
        if constexpr (!kCount && !kOcclusion) {
            if (ctx_.closest != nullptr && mailbox_ == nullptr) {
                const std::uint32_t first = bsp.begin(j);
                TestedIds tested{listed_ids_, listed_, kListed};
                if (ctx_.closest(wray_, ctx_.triangles, ctx_.order, bsp.footprints() + first, bsp.ids() + first,
                                 bsp.end(j) - first, ray, tested, best_)) {
                    for (std::uint32_t k = listed_; k < tested.count; ++k)
                        listed_filter_[(listed_ids_[k] >> 6) & 3u] |= std::uint64_t(1) << (listed_ids_[k] & 63u);
                    listed_ = tested.count;
                    if (best_.triangle != kNoHit) wray_.tfar = best_.t;
                    distinct_ = false;
                    return;
                }
            }
        }
        leaves(bsp, j, j, ray);
    }

    // Tests the untested triangles of leaves [j0, j1] whose footprint meets the ray's; true if the
    // ray is occluded (occlusion walks only).
    bool leaves(const TileBspView& bsp, std::uint32_t j0, std::uint32_t j1, std::uint32_t ray) {
        if constexpr (kCount) counters_->leaves += j1 - j0 + 1;
        const std::uint32_t first = bsp.begin(j0), count = bsp.end(j1) - first;
        if constexpr (kCount) counters_->vlf.entries += count;
        if (j1 > j0) distinct_ = false;  // a straddling triangle appears once per leaf
        const PackedIds ids = bsp.ids();
        const std::uint32_t* footprints = bsp.footprints();
        const Triangle* batch[8];
        std::uint32_t batch_ids[8];
        int n = 0;
        std::uint32_t passing[kScanChunk + 16];
        // Entries [a, b): those whose footprint meets the ray's, untested, go to the triangle test
        // in batches of 8; true when an occlusion walk is done.
        auto scan = [&](std::uint32_t a, std::uint32_t b) {
            for (std::uint32_t k = a; k < b; k += kScanChunk) {
                const std::uint32_t chunk = b - k < kScanChunk ? b - k : kScanChunk;
                const std::uint32_t found = ctx_.scan(footprints + k, chunk, ray, passing);
                for (std::uint32_t p = 0; p < found; ++p) {
                    const std::uint32_t id = ids[k + passing[p]];
                    if (already_tested(id)) continue;
                    batch[n] = ctx_.triangles + id;
                    batch_ids[n] = id;
                    if (++n == 8) {
                        if (test(batch, batch_ids, n)) return true;
                        n = 0;
                    }
                }
            }
            return false;
        };
        const std::uint32_t end = first + count, g0 = first / TileBspView::kGroup,
                            g1 = (end + TileBspView::kGroup - 1) / TileBspView::kGroup;
        // The ray's box on the tile's lattice (tile_footprint.hpp): groups pay when it is small.
        const std::uint32_t width = (ray & 0xFFu) + ((ray >> 16) & 0xFFu), height = ((ray >> 8) & 0xFFu) + (ray >> 24);
        if (bsp.groups() == nullptr || g1 - g0 <= kGroupScan || width > 255u + kGroupBox || height > 255u + kGroupBox) {
            if (scan(first, end)) return true;
        } else {
            // A long run (dense tiles): only the groups whose union footprint meets the ray's
            // (tile_bsp.hpp), in order, so the same entries pass in the same order as above.
            std::uint32_t groups[kScanChunk + 16];
            for (std::uint32_t h = g0; h < g1; h += kScanChunk) {
                const std::uint32_t chunk = g1 - h < kScanChunk ? g1 - h : kScanChunk;
                const std::uint32_t found = ctx_.scan(bsp.groups() + h, chunk, ray, groups);
                for (std::uint32_t p = 0; p < found; ++p) {
                    const std::uint32_t g = h + groups[p];
                    const std::uint32_t a = g * TileBspView::kGroup, b = a + TileBspView::kGroup;
                    if (scan(a < first ? first : a, b < end ? b : end)) return true;
                }
            }
        }
        const bool occluded = n > 0 && test(batch, batch_ids, n);
        distinct_ = false;  // later leaves may hold these triangles again
        return occluded;
    }

    // Mailboxing: the triangles a ray has tested go to a short list (searched once the ray has
    // left the run of distinct ids it started with, the first leaf, and only when a 256-bit filter
    // of the listed ids' low bits says the id may be there); the thread's mailbox, one stamp per
    // triangle, takes over with that list when it fills. Most rays never need it.
    bool already_tested(std::uint32_t id) {
        if (mailbox_ != nullptr) return mailbox_->seen(id);
        std::uint64_t& word = listed_filter_[(id >> 6) & 3u];
        const std::uint64_t bit = std::uint64_t(1) << (id & 63u);
        if (!distinct_ && (word & bit))
            for (std::uint32_t k = 0; k < listed_; ++k)
                if (listed_ids_[k] == id) return true;
        if (listed_ < kListed) {
            listed_ids_[listed_++] = id;
            word |= bit;
            return false;
        }
        mailbox_ = &Mailbox::local();
        mailbox_->begin(ctx_.triangle_count);
        for (std::uint32_t k = 0; k < listed_; ++k) mailbox_->seen(listed_ids_[k]);
        return mailbox_->seen(id);
    }

    // The triangle kernels (bit-exact with the scalar reference, which a lone triangle uses: a
    // SIMD call costs more than one scalar test).
    bool test(const Triangle* const* batch, const std::uint32_t* ids, int n) {
        if constexpr (kCount) counters_->triangle_tests += std::uint64_t(n);
        if (n == 1) {
            TriangleHit h;
            if (!intersect_triangle(wray_, *batch[0], h)) return false;
            if constexpr (kOcclusion) {
                best_.triangle = ids[0];
                return true;
            }
            if (nearer(h.t, ids[0])) {
                best_ = Hit{h.t, ids[0], h.u, h.v};
                wray_.tfar = h.t;
            }
            return false;
        }
        LaneHits lanes;
        if (n <= 4)
            ctx_.kernels->ray_x4(wray_, batch, n, lanes);
        else
            ctx_.kernels->ray_x8(wray_, batch, n, lanes);
        if constexpr (kOcclusion) {
            if (lanes.mask) {
                best_.triangle = ids[__builtin_ctz(lanes.mask)];
                return true;
            }
        } else {
            for (std::uint32_t m = lanes.mask; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                if (nearer(lanes.t[i], ids[i])) {
                    best_ = Hit{lanes.t[i], ids[i], lanes.u[i], lanes.v[i]};
                    wray_.tfar = lanes.t[i];
                }
            }
        }
        return false;
    }

    // Whether a hit at t on triangle id beats the best so far: nearer, or as near on a triangle of
    // smaller caller's id (so the answer does not depend on the order of the tests).
    bool nearer(float t, std::uint32_t id) const {
        return t < best_.t || (t == best_.t && best_.hit() && ctx_.order[id] < ctx_.order[best_.triangle]);
    }

    const ParallelSubfield& psf_;
    const WalkContext& ctx_;
    WatertightRay wray_;
    QueryCounters* counters_;
    Hit best_;
    static constexpr std::uint32_t kListed = 32;
    static constexpr std::uint32_t kScanChunk = 128;            // entries scanned per call of the kernel
    static constexpr std::uint32_t kGroupScan = kDirectGroups;  // longer runs (in groups) are scanned group-wise
    static constexpr std::uint32_t kGroupBox = 32;              // by rays whose box is at most this wide and high
    std::uint32_t listed_ids_[kListed + 16];  // ids tested in the first leaf, before the mailbox (+ 16: TestedIds)
    std::uint32_t listed_ = 0;
    std::uint64_t listed_filter_[4] = {0, 0, 0, 0};  // bit (id & 255) set: id may be listed
    bool distinct_ = true;                           // every id met so far came from one leaf (no repeats possible)
    Mailbox* mailbox_ = nullptr;
};

}  // namespace beamtrace::vlf
