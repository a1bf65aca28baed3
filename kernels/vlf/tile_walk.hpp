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

namespace beamtrace::vlf {

struct WalkContext {
    const TileGrid* grid = nullptr;
    const Triangle* triangles = nullptr;
    const TriangleKernels* kernels = nullptr;
};

template <bool kOcclusion, bool kFast, bool kCount>
class TileWalk {
public:
    TileWalk(const ParallelSubfield& psf, const WalkContext& ctx, const Ray& ray, Mailbox& mailbox, VlfCounters* counters)
        : psf_(psf), ctx_(ctx), wray_(make_watertight_ray(ray)), mailbox_(mailbox), counters_(counters) {}

    // Closest hit (or, for occlusion, any hit: best.triangle != kNoHit) along the segment of cr.
    Hit run(const CanonicalRay& cr) {
        const TileGrid& g = *ctx_.grid;
        int c = g.cell(cr.ox + cr.t0 * cr.dx), r = g.cell(cr.oy + cr.t0 * cr.dy);
        if constexpr (kFast) {
            visit(c, r, cr, cr.t0, cr.t1);
            return best_;
        }
        constexpr double kInf = std::numeric_limits<double>::infinity();
        const double inv_x = 1.0 / cr.dx, inv_y = 1.0 / cr.dy;
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
        if (ref.leaves == 1) return leaf(bsp, 0) || (!kOcclusion && double(best_.t) <= tb);
        const std::uint32_t ja = bsp.leaf(cr.oz + ta * cr.dz), jb = bsp.leaf(cr.oz + tb * cr.dz);
        if (cr.dz > 0.0) {
            for (std::uint32_t j = ja;; ++j) {
                if (leaf(bsp, j)) return true;
                const double end = j < jb ? (double(bsp.split(j)) - cr.oz) / cr.dz : tb;
                if (!kOcclusion && double(best_.t) <= end) return true;
                if (j >= jb) return false;
            }
        }
        for (std::uint32_t j = ja;; --j) {
            if (leaf(bsp, j)) return true;
            const double end = j > jb ? (double(bsp.split(j - 1)) - cr.oz) / cr.dz : tb;
            if (!kOcclusion && double(best_.t) <= end) return true;
            if (j <= jb) return false;
        }
    }

    // Tests the untested triangles of leaf j; true if the ray is occluded (occlusion walks only).
    bool leaf(const TileBspView& bsp, std::uint32_t j) {
        if constexpr (kCount) ++counters_->leaves;
        const std::uint32_t* ids = bsp.ids();
        const std::uint32_t e = bsp.end(j);
        const Triangle* batch[8];
        std::uint32_t batch_ids[8];
        int n = 0;
        for (std::uint32_t k = bsp.begin(j); k < e; ++k) {
            const std::uint32_t id = ids[k];
            if (mailbox_.seen(id)) continue;
            batch[n] = ctx_.triangles + id;
            batch_ids[n] = id;
            if (++n == 8) {
                if (test(batch, batch_ids, n)) return true;
                n = 0;
            }
        }
        return n > 0 && test(batch, batch_ids, n);
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
    Mailbox& mailbox_;
    VlfCounters* counters_;
    Hit best_;
};

}  // namespace beamtrace::vlf
