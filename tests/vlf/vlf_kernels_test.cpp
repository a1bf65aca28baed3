// The SIMD kernels of VLF-RT against their scalar references, on every instruction set this CPU
// has: the packet lookup (bit for bit the single-ray set-up, lane by lane, including rays that
// miss the box, zero direction components, NaNs, idle lanes) and the footprint scan.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>

#include "../kdtree/test_scenes.hpp"
#include "vlf/packet_start.hpp"
#include "vlf/tile_footprint.hpp"
#include "vlf/vlf_kernels.hpp"

using namespace beamtrace;
using namespace beamtrace::vlf;

namespace {

std::vector<Isa> simd_isas() {
    std::vector<Isa> out;
    for (Isa isa : {Isa::sse42, Isa::avx2, Isa::avx512})
        if (isa_available(isa)) out.push_back(isa);
    return out;
}

template <class T>
std::uint64_t bits(T v) {
    if constexpr (sizeof(T) == 8) return std::bit_cast<std::uint64_t>(v);
    else return std::bit_cast<std::uint32_t>(v);
}

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
                case 0: r.dir = Float3{0.0f, 0.0f, u(rng)}; break;
                case 1: r.dir = Float3{-0.0f, u(rng), 0.0f}; break;
                case 2: r.org.x = box.lower.x; break;
                case 3: r.dir = Float3{0.0f, 0.0f, 0.0f}; break;
                case 4: r.dir.y = std::nanf(""); break;
                case 5: r.tnear = 0.3f * e.x; r.tfar = 0.5f * e.x; break;
                case 6: r.tfar = -1.0f; break;
                default: break;
            }
            packet.set_ray(i, r);
        }
        packets.push_back(packet);
    }
    return packets;
}

}  // namespace

TEST(VlfKernels, PacketLookupEqualsTheSingleRaySetUpBitForBit) {
    const Scene scene = test::random_soup(300, 91);
    VlfOptions options;
    options.directions = 129;
    options.tiles = 37;
    VisibilityField::Impl field(scene, options);
    std::mt19937 rng(92);
    const std::vector<Packet16> packets = awkward_packets(scene.bounds(), rng, 3000);
    for (Isa isa : simd_isas()) {
        SCOPED_TRACE(isa_name(isa));
        std::size_t valid = 0;
        for (const Packet16& p : packets) {
            PacketLookup a, b;
            field.simd = &vlf_kernels(Isa::scalar);
            lookup_packet(field, p, a);
            field.simd = &vlf_kernels(isa);
            lookup_packet(field, p, b);
            ASSERT_EQ(a.valid, b.valid);
            for (std::uint32_t m = a.valid; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                ++valid;
                ASSERT_EQ(a.psf[i], b.psf[i]);
                for (auto [x, y] : {std::pair{a.ox[i], b.ox[i]}, {a.oy[i], b.oy[i]}, {a.oz[i], b.oz[i]},
                                    {a.dx[i], b.dx[i]}, {a.dy[i], b.dy[i]}, {a.dz[i], b.dz[i]}, {a.t0[i], b.t0[i]},
                                    {a.t1[i], b.t1[i]}, {a.inv_dx[i], b.inv_dx[i]}, {a.inv_dy[i], b.inv_dy[i]},
                                    {a.inv_dz[i], b.inv_dz[i]}})
                    ASSERT_EQ(bits(x), bits(y)) << "lane " << i;
                ASSERT_EQ(a.column[i], b.column[i]);
                ASSERT_EQ(a.row[i], b.row[i]);
                ASSERT_EQ(a.kx[i], b.kx[i]);
                ASSERT_EQ(a.ky[i], b.ky[i]);
                ASSERT_EQ(a.kz[i], b.kz[i]);
                ASSERT_EQ(bits(a.sx[i]), bits(b.sx[i]));
                ASSERT_EQ(bits(a.sy[i]), bits(b.sy[i]));
                ASSERT_EQ(bits(a.sz[i]), bits(b.sz[i]));
            }
        }
        EXPECT_GT(valid, 5000u);  // lanes that reach the box (many miss it on purpose)
    }
}

TEST(VlfKernels, FootprintScanEqualsScalar) {
    std::mt19937 rng(93);
    std::vector<std::uint32_t> footprints(300);
    for (std::uint32_t& f : footprints) {
        const std::uint32_t x0 = rng() % 256, y0 = rng() % 256;
        const std::uint32_t x1 = x0 + rng() % (256 - x0), y1 = y0 + rng() % (256 - y0);
        f = x0 | (y0 << 8) | ((255 - x1) << 16) | ((255 - y1) << 24);
    }
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
