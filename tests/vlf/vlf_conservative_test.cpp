// Conservativeness of a PSF's build: for random triangles (small, huge, slivers, parallel to the
// beam, through tile corners) and random beam directions, every triangle whose projection meets a
// tile (exact separating-axis check in double, no padding) is in that tile, in every tile-BSP leaf
// its depth range inside the tile's prism overlaps, with a footprint covering its part of the tile.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "vlf/build/parallel_subfield.hpp"
#include "vlf/build/prism_clip.hpp"
#include "vlf/query/tile_footprint.hpp"
#include "vlf/build/tile_rasteriser.hpp"

using namespace beamtrace;
using namespace beamtrace::vlf;

namespace {

// Whether the closed triangle (a, b, c) in the plane meets the closed square [x0, x1] x [y0, y1]:
// no separating axis among x, y and the triangle's three edge normals.
bool meets_square(const Vec3d* v, double x0, double x1, double y0, double y1) {
    const double tx0 = std::min({v[0].x, v[1].x, v[2].x}), tx1 = std::max({v[0].x, v[1].x, v[2].x});
    const double ty0 = std::min({v[0].y, v[1].y, v[2].y}), ty1 = std::max({v[0].y, v[1].y, v[2].y});
    if (tx1 < x0 || tx0 > x1 || ty1 < y0 || ty0 > y1) return false;
    const double sx[4] = {x0, x1, x1, x0}, sy[4] = {y0, y0, y1, y1};
    for (int e = 0; e < 3; ++e) {
        const Vec3d& a = v[e];
        const Vec3d& b = v[(e + 1) % 3];
        const double nx = -(b.y - a.y), ny = b.x - a.x;
        if (nx == 0.0 && ny == 0.0) continue;
        double tmin = 1e300, tmax = -1e300;
        for (int k = 0; k < 3; ++k) {
            const double p = nx * v[k].x + ny * v[k].y;
            tmin = std::min(tmin, p);
            tmax = std::max(tmax, p);
        }
        double smin = 1e300, smax = -1e300;
        for (int k = 0; k < 4; ++k) {
            const double p = nx * sx[k] + ny * sy[k];
            smin = std::min(smin, p);
            smax = std::max(smax, p);
        }
        if (smax < tmin || smin > tmax) return false;
    }
    return true;
}

struct Soup {
    std::vector<Triangle> triangles;
    Box box;
};

// Triangles of every awkward kind inside the unit cube.
Soup awkward_soup(std::mt19937& rng, int count) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
    Soup soup;
    for (int i = 0; i < count; ++i) {
        const Float3 c{u(rng), u(rng), u(rng)};
        const float size = i % 7 == 0 ? 0.8f : (i % 3 == 0 ? 1e-4f : 0.05f);
        Triangle t{c + Float3{s(rng), s(rng), s(rng)} * size, c + Float3{s(rng), s(rng), s(rng)} * size,
                   c + Float3{s(rng), s(rng), s(rng)} * size};
        if (i % 11 == 0) t.v2 = t.v0 + (t.v1 - t.v0) * 0.5f + Float3{0, 0, 1e-6f};  // a sliver
        if (i % 13 == 0) t.v2 = t.v0 * 0.5f + t.v1 * 0.5f;                          // a segment
        soup.triangles.push_back(t);
    }
    for (const Triangle& t : soup.triangles)
        for (const Float3& p : {t.v0, t.v1, t.v2}) soup.box.extend(p);
    return soup;
}

// Triangles lying along the beam (their projection a segment) and with corners on tile corners.
void add_beam_aligned(Soup& soup, const CanonicalFrame& f, const TileGrid& g, std::mt19937& rng) {
    std::uniform_int_distribution<int> cell(1, g.n - 1);
    const Float3 e1{float(f.e1.x), float(f.e1.y), float(f.e1.z)}, e2{float(f.e2.x), float(f.e2.y), float(f.e2.z)};
    const Float3 e3{float(f.e3.x), float(f.e3.y), float(f.e3.z)};
    const Float3 c{float(g.centre.x), float(g.centre.y), float(g.centre.z)};
    for (int k = 0; k < 40; ++k) {
        const Float3 p = c + e1 * float(g.edge(cell(rng)) * 0.5) + e2 * float(g.edge(cell(rng)) * 0.5);
        soup.triangles.push_back(Triangle{p, p + e3 * 0.2f, p + e1 * 0.01f + e2 * 0.01f});
        soup.triangles.push_back(Triangle{p, p + e1 * float(g.h), p + e2 * float(g.h)});
    }
}

}  // namespace

TEST(VlfConservative, EveryTriangleMeetingATileIsInItsLeavesWithItsFootprint) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::size_t checked_pairs = 0, grouped_entries = 0;
    for (int trial = 0; trial < 6; ++trial) {
        Float3 dir{u(rng), u(rng), std::fabs(u(rng)) + 0.05f};
        if (trial == 0) dir = Float3{0, 0, 1};
        if (trial == 1) dir = Float3{1, 1e-7f, 0};
        Soup soup = awkward_soup(rng, 600);
        const int n = trial % 2 == 0 ? 32 : 13;
        const int depth = trial % 3 == 0 ? 6 : 3;
        TileGrid grid = TileGrid::around(soup.box, n);
        const CanonicalFrame frame = CanonicalFrame::towards(normalize(dir));
        add_beam_aligned(soup, frame, grid, rng);
        Box box = soup.box;
        for (const Triangle& t : soup.triangles)
            for (const Float3& p : {t.v0, t.v1, t.v2}) box.extend(p);
        grid = TileGrid::around(box, n);
        std::vector<std::uint8_t> present(soup.triangles.size(), 1);
        const SubfieldInput input{&grid, soup.triangles, present, depth};
        const ParallelSubfield psf(frame, input);

        for (std::uint32_t id = 0; id < soup.triangles.size(); ++id) {
            const Triangle& t = soup.triangles[id];
            const Vec3d v[3] = {frame.point(t.v0, grid), frame.point(t.v1, grid), frame.point(t.v2, grid)};
            for (int r = 0; r < n; ++r)
                for (int c = 0; c < n; ++c) {
                    const double x0 = grid.edge(c), y0 = grid.edge(r);
                    if (!meets_square(v, x0, x0 + grid.h, y0, y0 + grid.h)) continue;
                    ++checked_pairs;
                    ClippedBox part;
                    ASSERT_TRUE(clip_to_prism(v, Prism{x0, x0 + grid.h, y0, y0 + grid.h}, part));
                    const TileRef ref = psf.tile(std::uint32_t(r * n + c));
                    ASSERT_GT(ref.leaves, 0u) << "triangle " << id << " missing from tile " << c << "," << r;
                    const TileBspView bsp = psf.view(ref);
                    const FootprintLattice lat = FootprintLattice::of_tile(grid, c, r);
                    const std::uint32_t need[4] = {FootprintLattice::cell((part.xlo - lat.x0) * lat.scale),
                                                   FootprintLattice::cell((part.ylo - lat.y0) * lat.scale),
                                                   FootprintLattice::cell((part.xhi - lat.x0) * lat.scale),
                                                   FootprintLattice::cell((part.yhi - lat.y0) * lat.scale)};
                    for (std::uint32_t j = 0; j < ref.leaves; ++j) {
                        const double lo = j == 0 ? -1e300 : double(bsp.split(j - 1));
                        const double hi = j + 1 == ref.leaves ? 1e300 : double(bsp.split(j));
                        if (part.zhi < lo || part.zlo > hi) continue;  // the leaf misses its depth range
                        bool found = false;
                        for (std::uint32_t k = bsp.begin(j); k < bsp.end(j); ++k) {
                            if (bsp.ids()[k] != id) continue;
                            found = true;
                            // The footprint holds every lattice cell of the part.
                            const std::uint32_t f = bsp.footprints()[k];
                            EXPECT_LE(f & 0xFFu, need[0]) << "triangle " << id;
                            EXPECT_LE((f >> 8) & 0xFFu, need[1]) << "triangle " << id;
                            EXPECT_GE(255u - ((f >> 16) & 0xFFu), need[2]) << "triangle " << id;
                            EXPECT_GE(255u - (f >> 24), need[3]) << "triangle " << id;
                            // Its group's union footprint holds it (every byte at most its byte).
                            if (bsp.groups() != nullptr) {
                                ++grouped_entries;
                                const std::uint32_t g = bsp.groups()[k / TileBspView::kGroup];
                                for (int shift = 0; shift < 32; shift += 8)
                                    EXPECT_LE((g >> shift) & 0xFFu, (f >> shift) & 0xFFu) << "triangle " << id;
                            }
                        }
                        ASSERT_TRUE(found) << "triangle " << id << " missing from leaf " << j << " of tile " << c << ","
                                           << r << " (trial " << trial << ")";
                    }
                }
        }
    }
    EXPECT_GT(checked_pairs, 10000u);
    (void)grouped_entries;  // dense tiles are rare in these soups: TileBsp.GroupsHoldTheirEntries covers them
}

TEST(VlfConservative, RasteriserIncludesEveryTileAnEdgeClipsAtACorner) {
    // An edge from one tile corner to the diagonally opposite one touches the two tiles beside
    // it at single points only: the 8-connected walk (Figure 1) includes them.
    const TileGrid grid = TileGrid::around(Box{{-1, -1, -1}, {1, 1, 1}}, 16);
    TileRasteriser raster(grid);
    const Vec3d v[3] = {{grid.edge(4), grid.edge(4), 0.0},
                        {grid.edge(8), grid.edge(8), 0.0},
                        {grid.edge(4), grid.edge(4), 1.0}};  // a segment in projection
    std::vector<std::pair<int, int>> tiles;
    raster.rasterise(v, [&](int c, int r) { tiles.emplace_back(c, r); });
    for (int k = 4; k < 8; ++k) {
        for (auto [c, r] : {std::pair{k, k}, std::pair{k - 1, k}, std::pair{k, k - 1}, std::pair{k + 1, k}})
            EXPECT_NE(std::find(tiles.begin(), tiles.end(), std::pair{c, r}), tiles.end()) << c << "," << r;
    }
}

// Groups (tile_bsp.hpp): a tile of at least kGroupedTile entries holds, for every 16 entries, a
// union footprint that holds each of their footprints; its leaves keep their entries (the same ids,
// reordered); smaller tiles have none.
TEST(TileBsp, GroupsHoldTheirEntries) {
    std::mt19937 rng(131);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int trial = 0; trial < 40; ++trial) {
        const std::size_t count = trial % 4 == 0 ? 100 : 300 + std::size_t(rng() % 2000);
        std::vector<DepthItem> items(count);
        for (std::size_t k = 0; k < count; ++k) {
            const float lo = u(rng), hi = lo + 0.05f * u(rng);
            const std::uint32_t x0 = rng() % 256, y0 = rng() % 256;
            const std::uint32_t x1 = std::min<std::uint32_t>(255, x0 + rng() % 20),
                                y1 = std::min<std::uint32_t>(255, y0 + rng() % 20);
            items[k] =
                DepthItem{std::uint32_t(k * 3), lo, hi, x0 | (y0 << 8) | ((255 - x1) << 16) | ((255 - y1) << 24)};
        }
        TileBspBuilder builder(4);
        std::vector<std::uint32_t> block;
        const std::uint32_t leaves = builder.build(items, block);
        const TileBspView bsp{block.data(), leaves};
        ASSERT_EQ(bsp.words(), block.size());
        if (bsp.entries() < TileBspView::kGroupedTile) {
            EXPECT_EQ(bsp.groups(), nullptr);
            continue;
        }
        ASSERT_NE(bsp.groups(), nullptr);
        for (std::uint32_t k = 0; k < bsp.entries(); ++k) {
            const std::uint32_t g = bsp.groups()[k / TileBspView::kGroup], f = bsp.footprints()[k];
            for (int shift = 0; shift < 32; shift += 8) ASSERT_LE((g >> shift) & 0xFFu, (f >> shift) & 0xFFu);
            ASSERT_EQ(bsp.ids()[k] % 3, 0u);
            ASSERT_EQ(f, items[bsp.ids()[k] / 3].footprint);  // each id keeps its own footprint
        }
    }
}

// TileBspView::leaf counts the splits below a depth, four at a time up to kCountedSplits splits and
// by a binary search beyond: both give the count a plain loop gives, at the splits themselves, a
// float's step either side of them, between them and outside them all.
TEST(TileBsp, LeafOfADepthCountsTheSplitsBelowIt) {
    std::mt19937 rng(907);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    int counted = 0, searched = 0;
    for (int trial = 0; trial < 60; ++trial) {
        const std::size_t count = 1 + std::size_t(rng() % (trial % 3 == 0 ? 40 : 4000));
        std::vector<DepthItem> items(count);
        for (std::size_t k = 0; k < count; ++k) {
            const float lo = 2.0f * u(rng) - 1.0f, hi = lo + 0.002f * u(rng);
            items[k] = DepthItem{std::uint32_t(k), lo, hi, 0u};
        }
        TileBspBuilder builder(trial % 4 * 2);
        std::vector<std::uint32_t> block;
        const std::uint32_t leaves = builder.build(items, block);
        const TileBspView view{block.data(), leaves};
        const std::uint32_t splits = view.leaves - 1;
        (splits <= TileBspView::kCountedSplits ? counted : searched) += 1;
        std::vector<double> depths{-1e30, -2.0, 0.0, 2.0, 1e30};
        for (std::uint32_t j = 0; j < splits; ++j) {
            const float s = view.split(j);
            depths.insert(depths.end(), {double(s), double(std::nextafter(s, -2.0f)), double(std::nextafter(s, 2.0f))});
        }
        for (int k = 0; k < 200; ++k) depths.push_back(2.4 * double(u(rng)) - 1.2);
        for (const double z : depths) {
            std::uint32_t below = 0;
            for (std::uint32_t j = 0; j < splits; ++j) below += view.split(j) < float(z) ? 1u : 0u;
            ASSERT_EQ(view.leaf(z), below) << "z " << z << ", " << splits << " splits";
        }
    }
    EXPECT_GT(counted, 10);
    EXPECT_GT(searched, 10);
}
