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

#include "beamtrace/vlf.hpp"
#include "common/triangle_kernels.hpp"
#include "common/triangle_reference.hpp"
#include "common/watertight_ray.hpp"
#include "vlf/canonical_ray.hpp"
#include "vlf/mailbox.hpp"
#include "vlf/parallel_subfield.hpp"
#include "vlf/tile_footprint.hpp"
#include "vlf/vlf_kernels.hpp"

namespace beamtrace::vlf {

struct WalkContext {
    const TileGrid* grid = nullptr;
    const Triangle* triangles = nullptr;
    std::size_t triangle_count = 0;
    const TriangleKernels* kernels = nullptr;
    ScanFootprintsFn scan = nullptr;
};

template <bool kOcclusion, bool kFast, bool kCount>
class TileWalk {
public:
    TileWalk(const ParallelSubfield& psf, const WalkContext& ctx, const WatertightRay& ray, VlfCounters* counters)
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
        auto next_x = [&] { return cr.dx > 0.0 ? (g.edge(c + 1) - cr.ox) * inv_x : cr.dx < 0.0 ? (g.edge(c) - cr.ox) * inv_x : kInf; };
        auto next_y = [&] { return cr.dy > 0.0 ? (g.edge(r + 1) - cr.oy) * inv_y : cr.dy < 0.0 ? (g.edge(r) - cr.oy) * inv_y : kInf; };
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
        if constexpr (kCount) ++counters_->tiles;
        const TileRef ref = psf_.tile(std::uint32_t(r) * std::uint32_t(ctx_.grid->n) + std::uint32_t(c));
        if (ref.leaves == 0) return false;
        const TileBspView bsp = psf_.view(ref);
        const FootprintLattice lattice = FootprintLattice::of_tile(*ctx_.grid, c, r);
        // The ray's footprint over [t0, t1] of its segment.
        auto footprint = [&](double t0, double t1) {
            const double xa = cr.ox + t0 * cr.dx, xb = cr.ox + t1 * cr.dx;
            const double ya = cr.oy + t0 * cr.dy, yb = cr.oy + t1 * cr.dy;
            return lattice.ray(xa < xb ? xa : xb, xa < xb ? xb : xa, ya < yb ? ya : yb, ya < yb ? yb : ya);
        };
        if (ref.leaves == 1) return leaves(bsp, 0, 0, footprint(ta, tb)) || (!kOcclusion && double(best_.t) <= tb);
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
            leaves(bsp, j, j, footprint(start, end));
            if (double(best_.t) <= end) return true;
            if (j == jb) return false;
            start = end;
        }
    }

    // Tests the untested triangles of leaves [j0, j1] whose footprint meets the ray's; true if the
    // ray is occluded (occlusion walks only).
    bool leaves(const TileBspView& bsp, std::uint32_t j0, std::uint32_t j1, std::uint32_t ray) {
        if constexpr (kCount) counters_->leaves += j1 - j0 + 1;
        const std::uint32_t first = bsp.begin(j0), count = bsp.end(j1) - first;
        if constexpr (kCount) counters_->entries += count;
        if (j1 > j0) distinct_ = false;  // a straddling triangle appears once per leaf
        const std::uint32_t* ids = bsp.ids() + first;
        const std::uint32_t* footprints = bsp.footprints() + first;
        const Triangle* batch[8];
        std::uint32_t batch_ids[8];
        int n = 0;
        std::uint32_t passing[kScanChunk + 16];
        for (std::uint32_t k = 0; k < count; k += kScanChunk) {
            const std::uint32_t chunk = count - k < kScanChunk ? count - k : kScanChunk;
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
        const bool occluded = n > 0 && test(batch, batch_ids, n);
        distinct_ = false;  // later leaves may hold these triangles again
        return occluded;
    }

    // Mailboxing: the triangles a ray has tested go to a short list (searched once the ray has
    // left the run of distinct ids it started with, the first leaf, and only when a 64-bit filter
    // of the listed ids' low bits says the id may be there); the thread's mailbox, one stamp per
    // triangle, takes over with that list when it fills. Most rays never need it.
    bool already_tested(std::uint32_t id) {
        if (mailbox_ != nullptr) return mailbox_->seen(id);
        const std::uint64_t bit = std::uint64_t(1) << (id & 63u);
        if (!distinct_ && (listed_filter_ & bit))
            for (std::uint32_t k = 0; k < listed_; ++k)
                if (listed_ids_[k] == id) return true;
        if (listed_ < kListed) {
            listed_ids_[listed_++] = id;
            listed_filter_ |= bit;
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
            if (h.t < best_.t) {
                best_ = Hit{h.t, ids[0], h.u, h.v};
                wray_.tfar = h.t;
            }
            return false;
        }
        LaneHits lanes;
        if (n <= 4) ctx_.kernels->ray_x4(wray_, batch, n, lanes);
        else ctx_.kernels->ray_x8(wray_, batch, n, lanes);
        if constexpr (kOcclusion) {
            if (lanes.mask) {
                best_.triangle = ids[__builtin_ctz(lanes.mask)];
                return true;
            }
        } else {
            for (std::uint32_t m = lanes.mask; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                if (lanes.t[i] < best_.t) {
                    best_ = Hit{lanes.t[i], ids[i], lanes.u[i], lanes.v[i]};
                    wray_.tfar = lanes.t[i];
                }
            }
        }
        return false;
    }

    const ParallelSubfield& psf_;
    const WalkContext& ctx_;
    WatertightRay wray_;
    VlfCounters* counters_;
    Hit best_;
    static constexpr std::uint32_t kListed = 32;
    static constexpr std::uint32_t kScanChunk = 128;  // entries scanned per call of the kernel
    std::uint32_t listed_ids_[kListed];  // ids tested in the first leaf, before the mailbox
    std::uint32_t listed_ = 0;
    std::uint64_t listed_filter_ = 0;
    bool distinct_ = true;  // every id met so far came from one leaf (no repeats possible)
    Mailbox* mailbox_ = nullptr;
};

}  // namespace beamtrace::vlf
