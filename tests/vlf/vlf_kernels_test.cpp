// The SIMD kernels of VLF-RT against their scalar references, on every instruction set this CPU
// has: the packet lookup (bit for bit the single-ray set-up, lane by lane, including rays that
// miss the box, zero direction components, NaNs, idle lanes), the footprint scan, and the kernels of
// batched one-tile occlusion (candidates, pair test, record stores). The leaf kernels are in
// vlf_entry_kernels_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>

#include "../kdtree/test_scenes.hpp"
#include "common/triangle_reference.hpp"
#include "vlf/query/entry_occlusion.hpp"
#include "vlf/stream/packet_start.hpp"
#include "vlf/query/tile_footprint.hpp"
#include "vlf/vlf_kernels.hpp"
#include "vlf_kernel_test_support.hpp"

using namespace beamtrace;
using namespace beamtrace::vlf;
using namespace beamtrace::vlf::test_support;

namespace {

// Packets of awkward rays: random, along the axes (zero and -0 components), from far away,
// starting on the box, NaN and zero directions, idle lanes; every fourth packet coherent.
std::vector<Packet16> awkward_packets(const Box& box, std::mt19937& rng, int count) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const Float3 c = box.center(), e = box.extent();
    std::vector<Packet16> packets;
    for (int p = 0; p < count; ++p) {
        Packet16 packet;
        packet.active = std::uint32_t(rng()) & 0xFFFFu;
        if (p % 3 == 0) packet.active = 0xFFFFu;
        for (int i = 0; i < 16; ++i) {
            Ray r;
            r.org = c + Float3{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z} * (p % 5 == 0 ? 8.0f : 0.8f);
            r.dir = Float3{u(rng), u(rng), u(rng)};
            if (p % 4 == 1) {  // a coherent packet: one PSF for every lane (its frame is broadcast)
                r.dir = Float3{0.3f, -0.2f, 0.9f} + Float3{u(rng), u(rng), u(rng)} * 1e-4f;
                packet.set_ray(i, r);
                continue;
            }
            switch ((p + i) % 9) {
                case 0:
                    r.dir = Float3{0.0f, 0.0f, u(rng)};
                    break;
                case 1:
                    r.dir = Float3{-0.0f, u(rng), 0.0f};
                    break;
                case 2:
                    r.org.x = box.lower.x;
                    break;
                case 3:
                    r.dir = Float3{0.0f, 0.0f, 0.0f};
                    break;
                case 4:
                    r.dir.y = std::nanf("");
                    break;
                case 5:
                    r.tnear = 0.3f * e.x;
                    r.tfar = 0.5f * e.x;
                    break;
                case 6:
                    r.tfar = -1.0f;
                    break;
                default:
                    break;
            }
            packet.set_ray(i, r);
        }
        packets.push_back(packet);
    }
    return packets;
}

// Every packet looked up by the scalar reference and by each SIMD kernel: the same valid lanes and,
// lane by lane, the same set-up bit for bit. Returns, per instruction set, the valid lanes, the
// lanes inside their first tile and the packets with no valid lane.
struct LookupCounts {
    std::size_t valid = 0, one_tile = 0, empty_packets = 0;
};
LookupCounts expect_same_lookups(VisibilityField::Impl& field, const std::vector<Packet16>& packets, Isa isa) {
    LookupCounts n;
    for (const Packet16& p : packets) {
        PacketLookup a, b;
        field.simd = &vlf_kernels(Isa::scalar);
        lookup_packet(field, p, a, true);
        field.simd = &vlf_kernels(isa);
        lookup_packet(field, p, b, true);
        EXPECT_EQ(a.valid, b.valid);
        bool same = a.valid == b.valid;
        n.empty_packets += a.valid == 0 ? 1 : 0;
        for (std::uint32_t m = a.valid; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            ++n.valid;
            EXPECT_EQ(a.psf[i], b.psf[i]);
            for (auto [x, y] : {std::pair{a.ox[i], b.ox[i]},
                                {a.oy[i], b.oy[i]},
                                {a.oz[i], b.oz[i]},
                                {a.dx[i], b.dx[i]},
                                {a.dy[i], b.dy[i]},
                                {a.dz[i], b.dz[i]},
                                {a.t0[i], b.t0[i]},
                                {a.t1[i], b.t1[i]},
                                {a.inv_dx[i], b.inv_dx[i]},
                                {a.inv_dy[i], b.inv_dy[i]},
                                {a.inv_dz[i], b.inv_dz[i]}})
                EXPECT_EQ(bits(x), bits(y)) << "lane " << i;
            EXPECT_EQ(a.column[i], b.column[i]);
            EXPECT_EQ(a.row[i], b.row[i]);
            EXPECT_EQ(a.kx[i], b.kx[i]);
            EXPECT_EQ(a.ky[i], b.ky[i]);
            EXPECT_EQ(a.kz[i], b.kz[i]);
            EXPECT_EQ(bits(a.sx[i]), bits(b.sx[i]));
            EXPECT_EQ(bits(a.sy[i]), bits(b.sy[i]));
            EXPECT_EQ(bits(a.sz[i]), bits(b.sz[i]));
            EXPECT_EQ(bits(a.z0[i]), bits(b.z0[i])) << "lane " << i;
            EXPECT_EQ(bits(a.z1[i]), bits(b.z1[i])) << "lane " << i;
            EXPECT_EQ(a.footprint[i], b.footprint[i]) << "lane " << i;
        }
        EXPECT_EQ(a.one_tile, b.one_tile);
        same = same && a.one_tile == b.one_tile;
        n.one_tile += std::uint32_t(__builtin_popcount(a.one_tile));
        if (!same) return n;  // one packet's report is enough
    }
    return n;
}

// Coherent packets passing the field's box: lines through points just inside, on and just outside
// its faces, edges and corners (relative offsets down to 1e-7), tangent to the surface there, from
// near and from 1e4 box sizes away, some lanes with a zero direction component sliding along a
// face. The SIMD lookups clip to the box before anything else and stop when no ray is left; every
// lane must still come out as the single-ray set-up has it.
std::vector<Packet16> packets_grazing_the_box(const WorldBox& wb, std::mt19937& rng, int count) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
    const float offsets[] = {-1e-3f, -1e-5f, -1e-7f, 0.0f, 1e-7f, 1e-5f, 1e-3f};
    const float distances[] = {0.5f, 3.0f, 1e4f};
    const Float3 lo{float(wb.lower[0]), float(wb.lower[1]), float(wb.lower[2])};
    const Float3 hi{float(wb.upper[0]), float(wb.upper[1]), float(wb.upper[2])};
    const Float3 size = hi - lo;
    std::vector<Packet16> packets;
    for (int p = 0; p < count; ++p) {
        // A point on the box's surface (a corner, a point of an edge or of a face), its outward
        // direction, then the point pushed in or out along it.
        Float3 target, outward{0.0f, 0.0f, 0.0f};
        for (int k = 0; k < 3; ++k) target[k] = lo[k] + u(rng) * size[k];
        const int kind = p % 3, axis = int(rng() % 3);
        for (int k = 0; k < 3; ++k)
            if (kind == 0 || (kind == 1 && k != axis) || (kind == 2 && k == axis)) {
                const bool up = rng() & 1;
                target[k] = up ? hi[k] : lo[k];
                outward[k] = up ? size[k] : -size[k];
            }
        target = target + outward * offsets[std::size_t(p) % std::size(offsets)];
        // A direction across the outward one: the line touches the surface near the target.
        const Float3 along = cross(normalize(outward), normalize(Float3{s(rng), s(rng), s(rng)}));
        const float distance = distances[std::size_t(p / 7) % std::size(distances)] * length(size);
        Packet16 packet;
        packet.active = 0xFFFFu;
        for (int i = 0; i < 16; ++i) {
            Ray r;
            r.org = target - along * distance + Float3{s(rng), s(rng), s(rng)} * (1e-7f * distance);
            r.dir = along;
            if (i == 3 && kind == 2) {  // sliding along the face: a zero component on its axis
                r.org = target;
                r.org[(axis + 1) % 3] -= 2.0f * size[(axis + 1) % 3];
                r.dir = Float3{1.0f, 1.0f, 1.0f};
                r.dir[axis] = (p % 2 == 0) ? 0.0f : -0.0f;
            }
            if (i == 5) r.tfar = 0.999999f * distance;  // ends just before the target
            packet.set_ray(i, r);
        }
        packets.push_back(packet);
    }
    return packets;
}

// The field the lookup tests use: 129 directions, 37 tiles a side.
std::unique_ptr<VisibilityField::Impl> lookup_field(const Scene& scene) {
    VlfOptions options;
    options.directions = 129;
    options.tiles = 37;
    return std::make_unique<VisibilityField::Impl>(scene, options);
}

}  // namespace

TEST(VlfKernels, PacketLookupEqualsTheSingleRaySetUpBitForBit) {
    const Scene scene = test::random_soup(300, 91);
    const std::unique_ptr<VisibilityField::Impl> field = lookup_field(scene);
    std::mt19937 rng(92);
    const std::vector<Packet16> packets = awkward_packets(scene.bounds(), rng, 3000);
    for (Isa isa : simd_isas()) {
        SCOPED_TRACE(isa_name(isa));
        const LookupCounts n = expect_same_lookups(*field, packets, isa);
        EXPECT_GT(n.valid, 5000u);    // lanes that reach the box (many miss it on purpose)
        EXPECT_GT(n.one_tile, 500u);  // segments inside their first tile
    }
}

TEST(VlfKernels, PacketLookupNeverDropsARayThatGrazesTheBox) {
    const Scene scene = test::random_soup(300, 94);
    const std::unique_ptr<VisibilityField::Impl> field = lookup_field(scene);
    std::mt19937 rng(95);
    const std::vector<Packet16> packets = packets_grazing_the_box(field->lookup.tables.box, rng, 6000);
    for (Isa isa : simd_isas()) {
        SCOPED_TRACE(isa_name(isa));
        const LookupCounts n = expect_same_lookups(*field, packets, isa);
        EXPECT_GT(n.valid, 20000u);         // rays that reach the box, many of them barely
        EXPECT_GT(n.empty_packets, 1000u);  // packets that miss it (the SIMD early exit)
        EXPECT_LT(n.empty_packets, 5000u);
    }
}

TEST(VlfKernels, FootprintScanEqualsScalar) {
    std::mt19937 rng(93);
    std::vector<std::uint32_t> footprints(300);
    for (std::uint32_t& f : footprints) f = random_triangle_footprint(rng);
    const ScanFootprintsFn scalar = vlf_kernels(Isa::scalar).scan_footprints;
    for (Isa isa : simd_isas()) {
        SCOPED_TRACE(isa_name(isa));
        const ScanFootprintsFn simd = vlf_kernels(isa).scan_footprints;
        for (int trial = 0; trial < 2000; ++trial) {
            const std::uint32_t count = std::uint32_t(rng() % footprints.size());
            const FootprintLattice lattice{0.0, 0.0, 1.0};
            const double x = double(rng() % 256), y = double(rng() % 256);
            const std::uint32_t ray = lattice.ray(x, x + double(rng() % 8), y, y + double(rng() % 8));
            std::uint32_t a[320], b[320];
            const std::uint32_t na = scalar(footprints.data(), count, ray, a);
            const std::uint32_t nb = simd(footprints.data(), count, ray, b);
            ASSERT_EQ(na, nb) << "count " << count;
            for (std::uint32_t k = 0; k < na; ++k) ASSERT_EQ(a[k], b[k]);
        }
    }
}

// The candidates of batched one-tile occlusion (tile_ray_batch.hpp) against the scalar reference:
// the same pairs in the same order, for runs of every length and offset in a tile (long ones go
// through the groups' union footprints), distinct ids or many repeats, footprints clustered (so
// that whole groups miss the ray) or spread.
TEST(VlfKernels, BatchCandidatesEqualScalar) {
    std::mt19937 rng(101);
    const BatchCandidatesFn scalar = vlf_kernels(Isa::scalar).batch_candidates;
    std::size_t pairs = 0;
    for (Isa isa : simd_isas()) {
        SCOPED_TRACE(isa_name(isa));
        const BatchCandidatesFn simd = vlf_kernels(isa).batch_candidates;
        for (int trial = 0; trial < 3000; ++trial) {
            const std::uint32_t entries = 1 + std::uint32_t(rng() % 700);
            const bool distinct = trial % 2 == 0;
            std::vector<std::uint32_t> ids(entries), footprints(entries);
            for (std::uint32_t k = 0; k < entries; ++k) {
                // Ids of all 24 bits (the candidates never touch triangles): odd multiples keep them distinct.
                ids[k] = distinct ? std::uint32_t((trial * 1000 + k) * 4099u % kMaxFieldTriangles)
                                  : std::uint32_t(rng() % 12 * 1398101u);
                // Clustered: entries of one group near one another (as the builder orders them).
                const std::uint32_t cx = (trial % 3 == 0) ? rng() % 256 : (k / 16 * 37) % 240;
                const std::uint32_t x0 = std::min<std::uint32_t>(255, cx + rng() % 16),
                                    y0 = (trial % 3 == 0) ? rng() % 256 : x0;
                const std::uint32_t x1 = x0 + rng() % (std::min<std::uint32_t>(256 - x0, 24)),
                                    y1 = y0 + rng() % (std::min<std::uint32_t>(256 - y0, 24));
                footprints[k] = x0 | (y0 << 8) | ((255 - x1) << 16) | ((255 - y1) << 24);
            }
            std::vector<std::uint32_t> groups((entries + 15) / 16, 0xFFFFFFFFu);
            for (std::uint32_t k = 0; k < entries; ++k)
                for (int shift = 0; shift < 32; shift += 8) {
                    const std::uint32_t mask = 0xFFu << shift;
                    if ((footprints[k] & mask) < (groups[k / 16] & mask))
                        groups[k / 16] = (groups[k / 16] & ~mask) | (footprints[k] & mask);
                }
            const std::uint32_t first = std::uint32_t(rng() % entries);
            const std::uint32_t count = std::uint32_t(rng() % (entries - first + 1));
            const std::uint32_t fp = random_ray_footprint(rng, 40);
            const std::uint32_t lane = std::uint32_t(rng() % 16);
            std::vector<std::uint32_t> ia(count + 16), la(count + 16), ib(count + 16), lb(count + 16);
            const std::uint32_t* g = trial % 4 == 1 ? nullptr : groups.data();  // a tile without groups
            const std::vector<std::uint32_t> words = packed(ids);
            const std::uint32_t na =
                scalar(g, footprints.data(), view(words), first, count, fp, distinct, lane, ia.data(), la.data());
            const std::uint32_t nb =
                simd(g, footprints.data(), view(words), first, count, fp, distinct, lane, ib.data(), lb.data());
            ASSERT_EQ(na, nb) << "trial " << trial;
            for (std::uint32_t k = 0; k < na; ++k) {
                ASSERT_EQ(ia[k], ib[k]) << "trial " << trial << " pair " << k;
                ASSERT_EQ(la[k], lane);
                ASSERT_EQ(lb[k], lane);
            }
            pairs += na;
        }
    }
    if (simd_isas().empty()) GTEST_SKIP() << "no SIMD instruction set on this CPU";
    EXPECT_GT(pairs, 10000u);
}

// The pair test of batched one-tile occlusion against the scalar reference, and the reference
// against the watertight test of each ray on its own: rays of every direction (so every axis
// permutation), pairs of all 16 lanes in any order, rays already occluded on entry.
TEST(VlfKernels, BatchTestEqualsScalarAndSingleRays) {
    const Scene scene = test::random_soup(300, 102, 0.5f);
    const std::span<const Triangle> tris = scene.triangles();
    std::mt19937 rng(103);
    const std::vector<Ray> rays = test::random_rays(scene.bounds(), 16 * 400, 104);
    const BatchTestFn scalar = vlf_kernels(Isa::scalar).batch_test;
    std::size_t occluded_rays = 0;
    for (std::size_t b = 0; b < rays.size() / 16; ++b) {
        TileRayBatch batch;
        batch.count = 16;
        WatertightRay w[16];
        for (std::uint32_t i = 0; i < 16; ++i) {
            w[i] = make_watertight_ray(rays[b * 16 + i]);
            const float o[3] = {w[i].org.x, w[i].org.y, w[i].org.z};
            TileRay r{};
            r.kx = w[i].kx;
            r.ky = w[i].ky;
            r.kz = w[i].kz;
            r.okx = o[w[i].kx];
            r.oky = o[w[i].ky];
            r.okz = o[w[i].kz];
            r.sx = w[i].sx;
            r.sy = w[i].sy;
            r.sz = w[i].sz;
            r.tnear = w[i].tnear;
            r.tfar = w[i].tfar;
            r.slot = i;
            batch.set(i, r);
        }
        const std::uint32_t count = std::uint32_t(rng() % 300);
        std::vector<std::uint32_t> ids(count), lanes(count);
        for (std::uint32_t p = 0; p < count; ++p) {
            ids[p] = std::uint32_t(rng() % tris.size());
            lanes[p] = std::uint32_t(rng() % 16);
        }
        const std::uint32_t before = b % 3 == 0 ? std::uint32_t(rng()) & 0xFFFFu : 0u;
        // The reference: each pair's ray on its own.
        std::uint32_t expected = before;
        for (std::uint32_t p = 0; p < count; ++p) {
            TriangleHit h;
            if (intersect_triangle(w[lanes[p]], tris[ids[p]], h)) expected |= 1u << lanes[p];
        }
        const std::uint32_t a = scalar(batch, tris.data(), ids.data(), lanes.data(), count, before);
        ASSERT_EQ(a, expected) << "batch " << b;
        occluded_rays += std::uint32_t(__builtin_popcount(a & ~before));
        for (Isa isa : simd_isas()) {
            SCOPED_TRACE(isa_name(isa));
            ASSERT_EQ(vlf_kernels(isa).batch_test(batch, tris.data(), ids.data(), lanes.data(), count, before), a)
                << "batch " << b;
        }
    }
    EXPECT_GT(occluded_rays, 150u);
}

// The records of one-tile rays: every instruction set's store writes the bytes the scalar
// reference writes (lanes not asked for untouched), each record field by field what the lookup
// and the packet hold.
TEST(VlfKernels, TileRayStoresEqualScalar) {
    const Scene scene = test::random_soup(300, 95);
    const std::unique_ptr<VisibilityField::Impl> field = lookup_field(scene);
    std::mt19937 rng(96);
    const std::vector<Packet16> packets = awkward_packets(scene.bounds(), rng, 600);
    const auto n = std::uint32_t(field->grid.n);
    const StoreTileRaysFn reference = vlf_kernels(Isa::scalar).store_tile_rays;
    std::size_t stored = 0;
    for (Isa isa : simd_isas()) {
        SCOPED_TRACE(isa_name(isa));
        const VlfKernels& k = vlf_kernels(isa);
        for (std::size_t p = 0; p < packets.size(); ++p) {
            PacketLookup l;
            k.lookup_packet(field->lookup.tables, packets[p], l, true);
            // Some lanes asked for in reverse order of places, to catch a lane written to another's.
            const std::uint32_t lanes = p % 2 ? l.one_tile : l.valid;
            std::vector<TileRay> want(17), got(17);
            std::memset(want.data(), 0xAB, want.size() * sizeof(TileRay));
            std::memset(got.data(), 0xAB, got.size() * sizeof(TileRay));
            TileRay* to_want[16];
            TileRay* to_got[16];
            for (int i = 0; i < 16; ++i) {
                const int place = p % 3 ? i : 15 - i;
                to_want[i] = &want[std::size_t(place)];
                to_got[i] = &got[std::size_t(place)];
            }
            const auto slot0 = std::uint32_t(16 * p + 7);
            reference(l, packets[p], lanes, n, slot0, to_want);
            k.store_tile_rays(l, packets[p], lanes, n, slot0, to_got);
            ASSERT_EQ(std::memcmp(want.data(), got.data(), want.size() * sizeof(TileRay)), 0) << p;
            for (std::uint32_t m = lanes; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                const TileRay& r = *to_got[i];
                ASSERT_EQ(r.tile, std::uint32_t(l.row[i]) * n + std::uint32_t(l.column[i]));
                ASSERT_EQ(r.slot, slot0 + std::uint32_t(i));
                const float o[3] = {packets[p].org_x[i], packets[p].org_y[i], packets[p].org_z[i]};
                ASSERT_EQ(bits(r.okx), bits(o[l.kx[i]]));
                ASSERT_EQ(bits(r.oky), bits(o[l.ky[i]]));
                ASSERT_EQ(bits(r.okz), bits(o[l.kz[i]]));
                ASSERT_EQ(bits(r.z1), bits(l.z1[i]));
                ASSERT_EQ(r.footprint, l.footprint[i]);
                ASSERT_EQ(bits(r.tfar), bits(packets[p].tfar[i]));
                ASSERT_EQ(r.kz, l.kz[i]);
                ++stored;
            }
        }
    }
    if (simd_isas().empty()) GTEST_SKIP() << "no SIMD instruction set on this CPU";
    EXPECT_GT(stored, 1000u);
}
