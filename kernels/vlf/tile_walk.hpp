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
#include "common/watertight_ray.hpp"
#include "vlf/canonical_ray.hpp"
#include "vlf/mailbox.hpp"
#include "vlf/parallel_subfield.hpp"
#include "vlf/tile_footprint.hpp"

namespace beamtrace::vlf {

struct WalkContext {
    const TileGrid* grid = nullptr;
    const Triangle* triangles = nullptr;
    std::size_t triangle_count = 0;
    const TriangleKernels* kernels = nullptr;
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
        if (ref.leaves == 1) return leaf(bsp, 0, cr, lattice, ta, tb) || (!kOcclusion && double(best_.t) <= tb);
        const std::uint32_t ja = bsp.leaf(cr.oz + ta * cr.dz), jb = bsp.leaf(cr.oz + tb * cr.dz);
        const bool forward = cr.dz > 0.0;
        double start = ta;
        for (std::uint32_t j = ja;; forward ? ++j : --j) {
            double end = tb;
            if (j != jb) end = (double(bsp.split(forward ? j : j - 1)) - cr.oz) * cr.inv_dz;
            end = end < start ? start : (end > tb ? tb : end);
            if (leaf(bsp, j, cr, lattice, start, end)) return true;
            if (!kOcclusion && double(best_.t) <= end) return true;
            if (j == jb) return false;
            start = end;
        }
    }

    // Tests the untested triangles of leaf j whose footprint meets the ray's over [ta, tb]; true
    // if the ray is occluded (occlusion walks only).
    bool leaf(const TileBspView& bsp, std::uint32_t j, const CanonicalRay& cr, const FootprintLattice& lattice,
              double ta, double tb) {
        if constexpr (kCount) ++counters_->leaves;
        const std::uint32_t first = bsp.begin(j), count = bsp.end(j) - first;
        const std::uint32_t* ids = bsp.ids() + first;
        const std::uint32_t* footprints = bsp.footprints() + first;
        const double xa = cr.ox + ta * cr.dx, xb = cr.ox + tb * cr.dx;
        const double ya = cr.oy + ta * cr.dy, yb = cr.oy + tb * cr.dy;
        const std::uint32_t ray = lattice.ray(xa < xb ? xa : xb, xa < xb ? xb : xa, ya < yb ? ya : yb, ya < yb ? yb : ya);
        const __m128i ray4 = _mm_set1_epi32(int(ray));
        const Triangle* batch[8];
        std::uint32_t batch_ids[8];
        int n = 0;
        auto take = [&](std::uint32_t id) {
            if (already_tested(id)) return false;
            batch[n] = ctx_.triangles + id;
            batch_ids[n] = id;
            if (++n < 8) return false;
            n = 0;
            return test(batch, batch_ids, 8);
        };
        std::uint32_t k = 0;
        for (; k + 4 <= count; k += 4)
            for (unsigned m = footprints_meet4(footprints + k, ray4); m; m &= m - 1)
                if (take(ids[k + unsigned(__builtin_ctz(m))])) return true;
        for (; k < count; ++k)
            if (footprints_meet(footprints[k], ray) && take(ids[k])) return true;
        ++leaves_done_;
        return n > 0 && test(batch, batch_ids, n);
    }

    // Mailboxing. The ids of one leaf are distinct, so while a ray is in its first leaf the ids it
    // tests only go to a small list; the thread's mailbox takes over (with that list) when the ray
    // reaches a second leaf or the list fills. Most rays never need it.
    bool already_tested(std::uint32_t id) {
        if (mailbox_ != nullptr) return mailbox_->seen(id);
        if (leaves_done_ == 0 && listed_ < kListed) {
            listed_ids_[listed_++] = id;
            return false;
        }
        mailbox_ = &Mailbox::local();
        mailbox_->begin(ctx_.triangle_count);
        for (std::uint32_t k = 0; k < listed_; ++k) mailbox_->seen(listed_ids_[k]);
        return mailbox_->seen(id);
    }

    bool test(const Triangle* const* batch, const std::uint32_t* ids, int n) {
        if constexpr (kCount) counters_->triangle_tests += std::uint64_t(n);
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
    std::uint32_t listed_ids_[kListed];  // ids tested in the first leaf, before the mailbox
    std::uint32_t listed_ = 0, leaves_done_ = 0;
    Mailbox* mailbox_ = nullptr;
};

}  // namespace beamtrace::vlf
