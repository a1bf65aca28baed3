#pragma once
// The packet lookup written once over xsimd batches; included only by the per-ISA units. Every
// step repeats the single-ray set-up's operations in the same order (with -ffp-contract=off), so
// each lane's result is bit-identical to DirectionSet::Impl::nearest + make_canonical_ray.
// Only xsimd functions (templated on the architecture) and this file's internal-linkage helpers
// are used, so no inline function compiled for one instruction set can replace another's.
#include <cstdint>
#include <type_traits>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

#include "vlf/stream/packet_lookup.hpp"

namespace beamtrace::vlf {
namespace {

// Gathers through the instruction set's own gather where it has one (xsimd 8.1 falls back to
// element-by-element inserts for these), else element by element.
template <class Arch, class T, class I>
xsimd::batch<T, Arch> gather(const T* base, const xsimd::batch<I, Arch>& index) {
    using B = xsimd::batch<T, Arch>;
    constexpr bool avx512 = std::is_base_of_v<xsimd::avx512f, Arch>;
    constexpr bool avx2 = std::is_base_of_v<xsimd::avx2, Arch>;
    if constexpr (avx512 && std::is_same_v<T, float>)
        return B(_mm512_i32gather_ps(index, base, 4));
    else if constexpr (avx512 && std::is_same_v<T, std::int32_t>)
        return B(_mm512_i32gather_epi32(index, base, 4));
    else if constexpr (avx512 && std::is_same_v<T, double>)
        return B(_mm512_i64gather_pd(index, base, 8));
    else if constexpr (avx2 && std::is_same_v<T, float>)
        return B(_mm256_i32gather_ps(base, index, 4));
    else if constexpr (avx2 && std::is_same_v<T, std::int32_t>)
        return B(_mm256_i32gather_epi32(reinterpret_cast<const int*>(base), index, 4));
    else if constexpr (avx2 && std::is_same_v<T, double>)
        return B(_mm256_i64gather_pd(base, index, 8));
    else {
        alignas(64) I at[B::size];
        alignas(64) T values[B::size];
        index.store_aligned(at);
        for (std::size_t k = 0; k < B::size; ++k) values[k] = base[at[k]];
        return B::load_aligned(values);
    }
}

// Float: the nearest direction of rays [base, base + W), and their watertight set-up.
template <class Arch>
void nearest_directions(const LookupTables& t, const Packet16& p, int base, std::int32_t* psf, float* ok,
                        PacketLookup& out) {
    using BF = xsimd::batch<float, Arch>;
    using BI = xsimd::batch<std::int32_t, Arch>;
    const BF zero(0.0f), one(1.0f), inf(HUGE_VALF);
    BF x = BF::load_aligned(p.dir_x + base), y = BF::load_aligned(p.dir_y + base), z = BF::load_aligned(p.dir_z + base);
    const BF s0 = (xsimd::abs(x) + xsimd::abs(y)) + xsimd::abs(z);
    const auto good = (s0 > zero) & (s0 < inf);
    // Lanes without a usable direction look up +z (their result is never used).
    x = xsimd::select(good, x, zero);
    y = xsimd::select(good, y, zero);
    z = xsimd::select(good, z, one);
    const BF s = (xsimd::abs(x) + xsimd::abs(y)) + xsimd::abs(z);
    const BF inv = xsimd::select(z < zero, BF(-1.0f), one) / s;
    const BF half(t.half_table);
    const BI last(t.table - 1), izero(0);
    BI iu = xsimd::to_int((x * inv + one) * half), iv = xsimd::to_int((y * inv + one) * half);
    iu = xsimd::min(xsimd::max(iu, izero), last);
    iv = xsimd::min(xsimd::max(iv, izero), last);
    const BI words = (iv * BI(t.table) + iu) * BI(t.pairs_per_cell);
    // Coherent packets (primary rays) mostly fall in one table cell: its candidates are read once.
    alignas(64) std::int32_t word[BI::size];
    words.store_aligned(word);
    bool one_cell = true;
    for (std::size_t i = 1; i < BI::size; ++i) one_cell &= word[i] == word[0];
    const BI low(0xFFFF);
    BF best(0.0f);  // the index, as a float (exact below 2^24)
    BF best_dot(0.0f);
    for (int k = 0; k < t.pairs_per_cell; ++k) {
        const BI pair = one_cell ? BI(t.candidate_pairs[word[0] + k]) : gather<Arch>(t.candidate_pairs, words + BI(k));
        for (int half_word = 0; half_word < 2; ++half_word) {
            const BI c = half_word == 0 ? (pair & low) : ((pair >> 16) & low);
            BF d;
            if (one_cell) {
                const std::uint32_t i = std::uint32_t(t.candidate_pairs[word[0] + k]) >> (16 * half_word) & 0xFFFFu;
                d = (x * BF(t.dir_x[i]) + y * BF(t.dir_y[i])) + z * BF(t.dir_z[i]);
            } else {
                d = (x * gather<Arch>(t.dir_x, c) + y * gather<Arch>(t.dir_y, c)) + z * gather<Arch>(t.dir_z, c);
            }
            if (k == 0 && half_word == 0) {
                best = xsimd::to_float(c);
                best_dot = d;
                continue;
            }
            const auto take = xsimd::abs(d) > xsimd::abs(best_dot);
            best = xsimd::select(take, xsimd::to_float(c), best);
            best_dot = xsimd::select(take, d, best_dot);
        }
    }
    xsimd::to_int(best).store_aligned(psf + base);
    xsimd::select(good, one, zero).store_aligned(ok + base);

    // make_watertight_ray: the dominant axis kz, the others kx, ky (swapped when d[kz] < 0), shear.
    const BF two(2.0f), ax = xsimd::abs(x), ay = xsimd::abs(y), az = xsimd::abs(z);
    const BF kz = xsimd::select(ax > ay, xsimd::select(ax > az, zero, two), xsimd::select(ay > az, one, two));
    const BF kx0 = xsimd::select(kz == two, zero, kz + one);
    const BF ky0 = xsimd::select(kx0 == two, zero, kx0 + one);
    auto pick = [&](const BF& k) { return xsimd::select(k == zero, x, xsimd::select(k == one, y, z)); };
    const BF dz = pick(kz);
    const auto flip = dz < zero;
    const BF kx = xsimd::select(flip, ky0, kx0), ky = xsimd::select(flip, kx0, ky0);
    (pick(kx) / dz).store_aligned(out.sx + base);
    (pick(ky) / dz).store_aligned(out.sy + base);
    (one / dz).store_aligned(out.sz + base);
    xsimd::to_int(kx).store_aligned(out.kx + base);
    xsimd::to_int(ky).store_aligned(out.ky + base);
    xsimd::to_int(kz).store_aligned(out.kz + base);
}

// Double, after canonical_rays: for rays [base, base + W), what tile_walk.hpp computes for a segment in its first
// tile: whether it is (first_tile_exit), the depths of its ends, its footprint (FootprintLattice).
template <class Arch>
void first_tiles(const LookupTables& t, const xsimd::batch<double, Arch>* co, const xsimd::batch<double, Arch>* cd,
                 const xsimd::batch<double, Arch>* inv_cd, const xsimd::batch<double, Arch>& t0,
                 const xsimd::batch<double, Arch>& t1, const xsimd::batch<double, Arch>* cell, int base,
                 PacketLookup& out, double* one_tile, double* footprint) {
    using BD = xsimd::batch<double, Arch>;
    const BD zero(0.0), one(1.0), inf(HUGE_VAL), radius(t.radius), h(t.h);
    // TileGrid::edge(i) = -radius + i * h.
    auto edge = [&](const BD& i) { return -radius + i * h; };
    BD exit[2];
    for (int a = 0; a < 2; ++a) {
        const BD& inv = inv_cd[a];  // 1 / cd[a], the canonical ray's own (the same division)
        exit[a] = xsimd::select(cd[a] > zero, (edge(cell[a] + one) - co[a]) * inv,
                                xsimd::select(cd[a] < zero, (edge(cell[a]) - co[a]) * inv, inf));
    }
    BD e = xsimd::select(exit[0] < exit[1], exit[0], exit[1]);
    e = xsimd::select(e < t1, e, t1);
    e = xsimd::select(e > t0, e, t0);
    xsimd::select(e >= t1, one, zero).store_aligned(one_tile + base);
    alignas(64) double z[8];
    (co[2] + t0 * cd[2]).store_aligned(z);
    for (int k = 0; k < int(BD::size); ++k) out.z0[base + k] = float(z[k]);
    (co[2] + t1 * cd[2]).store_aligned(z);
    for (int k = 0; k < int(BD::size); ++k) out.z1[base + k] = float(z[k]);
    // FootprintLattice::ray over [t0, t1]: floor of the lattice coordinate, clamped to [0, 255].
    const BD scale(t.lattice_scale), pad(t.pad), top(255.0);
    auto cell_of = [&](const BD& q) {
        return xsimd::select(q < one, zero, xsimd::select(q >= top, top, xsimd::trunc(q)));
    };
    BD lo[2], hi[2];
    for (int a = 0; a < 2; ++a) {
        const BD origin = edge(cell[a]) - pad;
        const BD p = co[a] + t0 * cd[a], q = co[a] + t1 * cd[a];
        const auto less = p < q;
        lo[a] = cell_of((xsimd::select(less, p, q) - origin) * scale);
        hi[a] = cell_of((xsimd::select(less, q, p) - origin) * scale);
    }
    // c | d << 8 | (255 - a) << 16 | (255 - b) << 24, exact in double.
    const BD word = ((hi[0] + hi[1] * BD(256.0)) + (top - lo[0]) * BD(65536.0)) + (top - lo[1]) * BD(16777216.0);
    word.store_aligned(footprint + base);
}

// Double, first of all: rays [base, base + W) cut to the box: their parameter ranges [t0, t1] (in
// in[6], in[7], replaced) and whether anything of them is left (ok).
template <class Arch>
void clip_to_box(const LookupTables& t, double (*in)[16], int base, double* ok) {
    using BD = xsimd::batch<double, Arch>;
    const BD zero(0.0), inf(HUGE_VAL);
    BD t0 = BD::load_aligned(in[6] + base), t1 = BD::load_aligned(in[7] + base);
    auto good = zero == zero;  // all lanes, narrowed below
    for (int k = 0; k < 3; ++k) {
        const BD o = BD::load_aligned(in[k] + base), d = BD::load_aligned(in[3 + k] + base);
        good = good & (xsimd::abs(o) < inf);
        const BD lo(t.box.lower[k]), hi(t.box.upper[k]);
        const auto flat = d == zero;
        good = good & (~flat | ((o >= lo) & (o <= hi)));
        const BD inv = BD(1.0) / xsimd::select(flat, BD(1.0), d);
        const BD ta = (lo - o) * inv, tb = (hi - o) * inv;
        const BD near = xsimd::select(tb < ta, tb, ta), far = xsimd::select(ta < tb, tb, ta);
        t0 = xsimd::select(flat, t0, xsimd::select(t0 < near, near, t0));
        t1 = xsimd::select(flat, t1, xsimd::select(far < t1, far, t1));
    }
    good = good & (t0 <= t1);
    t0.store_aligned(in[6] + base);
    t1.store_aligned(in[7] + base);
    xsimd::select(good, BD(1.0), zero).store_aligned(ok + base);
}

// Double, after the nearest directions: the clipped rays [base, base + W) rotated into their PSF's frame, first tile.
template <class Arch>
void canonical_rays(const LookupTables& t, const double (*in)[16], const std::int64_t* psf, bool one_psf, int base,
                    PacketLookup& out, double* cell_x, double* cell_y, bool first, double* one_tile,
                    double* footprint) {
    using BD = xsimd::batch<double, Arch>;
    using BL = xsimd::batch<std::int64_t, Arch>;
    const BD zero(0.0);
    BD o[3], d[3];
    for (int k = 0; k < 3; ++k) {
        o[k] = BD::load_aligned(in[k] + base);
        d[k] = BD::load_aligned(in[3 + k] + base);
    }
    const BD t0 = BD::load_aligned(in[6] + base), t1 = BD::load_aligned(in[7] + base);
    // Rotation: p' = M (p - centre), d' = M d with M's rows e1, e2, e3 of the lane's PSF.
    BD m[9];
    if (one_psf) {  // coherent packets (primary rays) mostly share one PSF: no gathers
        for (int c = 0; c < 9; ++c) m[c] = BD(t.frames[std::size_t(c) * std::size_t(t.count) + std::size_t(psf[0])]);
    } else {
        const BL index = BL::load_aligned(psf + base);
        for (int c = 0; c < 9; ++c) m[c] = gather<Arch>(t.frames + std::size_t(c) * std::size_t(t.count), index);
    }
    const BD px = o[0] - BD(t.centre[0]), py = o[1] - BD(t.centre[1]), pz = o[2] - BD(t.centre[2]);
    BD co[3], cd[3];
    for (int r = 0; r < 3; ++r) {
        co[r] = (m[3 * r] * px + m[3 * r + 1] * py) + m[3 * r + 2] * pz;
        cd[r] = (m[3 * r] * d[0] + m[3 * r + 1] * d[1]) + m[3 * r + 2] * d[2];
    }
    co[0].store_aligned(out.ox + base);
    co[1].store_aligned(out.oy + base);
    co[2].store_aligned(out.oz + base);
    cd[0].store_aligned(out.dx + base);
    cd[1].store_aligned(out.dy + base);
    cd[2].store_aligned(out.dz + base);
    const BD inv_cd[3] = {BD(1.0) / cd[0], BD(1.0) / cd[1], BD(1.0) / cd[2]};
    inv_cd[0].store_aligned(out.inv_dx + base);
    inv_cd[1].store_aligned(out.inv_dy + base);
    inv_cd[2].store_aligned(out.inv_dz + base);
    t0.store_aligned(out.t0 + base);
    t1.store_aligned(out.t1 + base);
    // Tile of the start point, as TileGrid::cell: floor((c + R) / h) clamped to [0, n - 1].
    const BD radius(t.radius), inv_h(t.inv_h), last(double(t.tiles - 1));
    BD cell[2];
    for (int axis = 0; axis < 2; ++axis) {
        const BD f = xsimd::floor(((co[axis] + t0 * cd[axis]) + radius) * inv_h);
        cell[axis] = xsimd::select(f < zero, zero, xsimd::select(f >= BD(double(t.tiles)), last, f));
        cell[axis].store_aligned((axis == 0 ? cell_x : cell_y) + base);
    }
    if (first) first_tiles<Arch>(t, co, cd, inv_cd, t0, t1, cell, base, out, one_tile, footprint);
}

template <class Arch>
void lookup_packet_simd(const LookupTables& t, const Packet16& p, PacketLookup& out, bool first_tiles) {
    constexpr int WF = int(xsimd::batch<float, Arch>::size), WD = int(xsimd::batch<double, Arch>::size);
    alignas(64) double in[8][16];
    for (int i = 0; i < 16; ++i) {
        in[0][i] = p.org_x[i];
        in[1][i] = p.org_y[i];
        in[2][i] = p.org_z[i];
        in[3][i] = p.dir_x[i];
        in[4][i] = p.dir_y[i];
        in[5][i] = p.dir_z[i];
        in[6][i] = p.tnear[i];
        in[7][i] = p.tfar[i];
    }
    // The box first: a packet none of whose rays reaches it needs no direction (primary rays of a
    // mesh framed from outside: more than half of the packets).
    alignas(64) double ray_ok[16];
    for (int base = 0; base < 16; base += WD) clip_to_box<Arch>(t, in, base, ray_ok);
    std::uint32_t clipped = 0;
    for (int i = 0; i < 16; ++i) clipped |= std::uint32_t(ray_ok[i] != 0.0) << i;
    if ((clipped & p.active) == 0) {
        out.valid = 0;
        out.one_tile = 0;
        return;
    }
    alignas(64) std::int32_t psf[16];
    alignas(64) float dir_ok[16];
    for (int base = 0; base < 16; base += WF) nearest_directions<Arch>(t, p, base, psf, dir_ok, out);
    alignas(64) std::int64_t psf64[16];
    bool one_psf = true;
    for (int i = 0; i < 16; ++i) {
        psf64[i] = psf[i];
        one_psf &= psf[i] == psf[0];
    }
    alignas(64) double cell_x[16], cell_y[16], one_tile[16], footprint[16];
    for (int base = 0; base < 16; base += WD)
        canonical_rays<Arch>(t, in, psf64, one_psf, base, out, cell_x, cell_y, first_tiles, one_tile, footprint);
    std::uint32_t valid = 0, in_tile = 0;
    for (int i = 0; i < 16; ++i) {
        out.psf[i] = std::uint32_t(psf[i]);
        out.column[i] = std::int32_t(cell_x[i]);
        out.row[i] = std::int32_t(cell_y[i]);
        valid |= std::uint32_t(dir_ok[i] != 0.0f && ray_ok[i] != 0.0) << i;
        if (!first_tiles) continue;
        out.footprint[i] = std::uint32_t(std::int64_t(footprint[i]));
        in_tile |= std::uint32_t(one_tile[i] != 0.0) << i;
    }
    out.valid = valid & p.active;
    out.one_tile = in_tile & out.valid;
}

}  // namespace
}  // namespace beamtrace::vlf
