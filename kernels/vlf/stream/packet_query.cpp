// Packet queries: the 16 lookups at once, then each ray's own walk.
#include <cmath>

#include "common/ray_validity.hpp"
#include "vlf/directions/direction_set_impl.hpp"
#include "vlf/query/field_query.hpp"
#include "vlf/stream/packet_start.hpp"

namespace beamtrace {
namespace {

// The lookups lane by lane, exactly as a single-ray query makes them.
void lookup_lanes(const VisibilityField::Impl& f, const Packet16& p, vlf::PacketLookup& out, bool first_tiles) {
    out.valid = 0;
    out.one_tile = 0;
    for (std::uint32_t m = p.active; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        const float s = std::fabs(p.dir_x[i]) + std::fabs(p.dir_y[i]) + std::fabs(p.dir_z[i]);
        if (!(s > 0.0f && s < kInfinity)) continue;
        const auto nearest = detail::Access::impl(f.directions).nearest(p.dir_x[i], p.dir_y[i], p.dir_z[i]);
        vlf::CanonicalRay cr;
        if (!vlf::make_canonical_ray(f.frames[nearest.index], f.grid, f.world_box, p.ray(i), cr)) continue;
        out.psf[i] = nearest.index;
        out.ox[i] = cr.ox;
        out.oy[i] = cr.oy;
        out.oz[i] = cr.oz;
        out.dx[i] = cr.dx;
        out.dy[i] = cr.dy;
        out.dz[i] = cr.dz;
        out.t0[i] = cr.t0;
        out.t1[i] = cr.t1;
        out.column[i] = cr.column;
        out.row[i] = cr.row;
        out.inv_dx[i] = cr.inv_dx;
        out.inv_dy[i] = cr.inv_dy;
        out.inv_dz[i] = cr.inv_dz;
        const WatertightRay w = make_watertight_ray(p.ray(i));
        out.kx[i] = w.kx;
        out.ky[i] = w.ky;
        out.kz[i] = w.kz;
        out.sx[i] = w.sx;
        out.sy[i] = w.sy;
        out.sz[i] = w.sz;
        out.valid |= 1u << i;
        if (!first_tiles) continue;
        out.z0[i] = float(cr.oz + cr.t0 * cr.dz);
        out.z1[i] = float(cr.oz + cr.t1 * cr.dz);
        out.footprint[i] =
            vlf::ray_footprint(vlf::FootprintLattice::of_tile(f.grid, cr.column, cr.row), cr, cr.t0, cr.t1);
        out.one_tile |= std::uint32_t(vlf::segment_in_first_tile<false>(f.grid, cr)) << i;
    }
}

}  // namespace

namespace vlf {

void lookup_packet(const VisibilityField::Impl& f, const Packet16& p, PacketLookup& out, bool first_tiles) {
    if (f.simd->lookup_packet)
        f.simd->lookup_packet(f.lookup.tables, p, out, first_tiles);
    else
        lookup_lanes(f, p, out, first_tiles);
    out.valid &= segment_lanes(p);  // rays that describe no segment report nothing
    out.one_tile &= out.valid;
}

void start_packet(const VisibilityField::Impl& f, const Packet16& p, PacketStart& s) {
    lookup_packet(f, p, s.lookup);
    const vlf::PacketLookup& l = s.lookup;
    const auto n = std::uint32_t(f.grid.n);
    const ParallelSubfield* last_psf = nullptr;
    std::uint32_t last_tile = 0xFFFFFFFFu;
    for (std::uint32_t m = l.valid; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        s.psf[i] = &f.psf(l.psf[i]);
        s.tile[i] = std::uint32_t(l.row[i]) * n + std::uint32_t(l.column[i]);
        if (s.psf[i] == last_psf && s.tile[i] == last_tile) continue;  // coherent packets: once per tile
        s.psf[i]->prefetch_tile(s.tile[i]);
        last_psf = s.psf[i];
        last_tile = s.tile[i];
    }
}

void prefetch_first_blocks(const PacketStart& s) {
    const ParallelSubfield* last_psf = nullptr;
    std::uint32_t last_tile = 0xFFFFFFFFu;
    for (std::uint32_t m = s.lookup.valid; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        if (s.psf[i] == last_psf && s.tile[i] == last_tile) continue;  // coherent packets: once per tile
        last_psf = s.psf[i];
        last_tile = s.tile[i];
        const TileRef ref = s.psf[i]->tile(s.tile[i]);
        if (ref.leaves) s.psf[i]->prefetch_block(ref, 0, 128);
    }
}

}  // namespace vlf

void VisibilityField::intersect(const Packet16& packet, PacketHits16& hits, VlfMode mode) const {
    const Impl& f = *impl_;
    const auto guard = f.reading();
    vlf::PacketStart s;
    vlf::start_packet(f, packet, s);
    vlf::prefetch_first_blocks(s);
    for (int i = 0; i < 16; ++i) hits.set_hit(i, Hit{});
    for (std::uint32_t m = s.lookup.valid; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        hits.set_hit(i, vlf::walk_field<false, false>(f, *s.psf[i], s.lookup.ray(i), s.lookup.watertight(i, packet),
                                                      mode, nullptr));
    }
}

std::uint32_t VisibilityField::occluded(const Packet16& packet, VlfMode mode) const {
    const Impl& f = *impl_;
    const auto guard = f.reading();
    vlf::PacketStart s;
    vlf::start_packet(f, packet, s);
    vlf::prefetch_first_blocks(s);
    std::uint32_t bits = 0;
    for (std::uint32_t m = s.lookup.valid; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        if (vlf::walk_field<true, false>(f, *s.psf[i], s.lookup.ray(i), s.lookup.watertight(i, packet), mode, nullptr)
                .hit())
            bits |= 1u << i;
    }
    return bits;
}

}  // namespace beamtrace
