// Adaptive tile splitting (section 4.2) through the public Mlrta: grids of pinhole-camera packets
// traced with every combination of split factor, minimum and initial tile size, frustum test,
// entry-point search order, stuck-tile rule and thread count give, ray by ray, the kd-tree's closest
// hits and occlusion answers; the tiles the observer sees partition the grid; settings are validated.
#include <gtest/gtest.h>

#include <mutex>

#include "beamtrace/error.hpp"
#include "hand_tree.hpp"
#include "mlrta/covered_leaves.hpp"

using namespace beamtrace;
using namespace beamtrace::mlrta;
using namespace beamtrace::mlrta::test;

namespace {

struct Image {
    Camera camera;
    std::vector<Packet16> packets;
    PacketGrid grid;
    std::vector<Hit> want;             // kd-tree closest hit per packet lane
    std::vector<std::uint32_t> shade;  // kd-tree occlusion bits per packet, with finite segments
    std::vector<Packet16> short_packets;

    Image(const KdTree& tree, const Camera& cam) : camera(cam), packets(cam.packets()) {
        grid = PacketGrid{packets.data(), cam.width / 4, cam.height / 4};
        short_packets = packets;
        for (std::size_t p = 0; p < packets.size(); ++p) {
            for (int i = 0; i < 16; ++i) {
                short_packets[p].tfar[i] = 0.5f + float((p * 16 + std::size_t(i)) % 13) * 0.45f;
                want.push_back(tree.intersect(packets[p].ray(i)));
            }
            std::uint32_t bits = 0;
            for (int i = 0; i < 16; ++i) bits |= tree.occluded(short_packets[p].ray(i)) ? 1u << i : 0u;
            shade.push_back(bits);
        }
    }
};

::testing::AssertionResult same_as_kd(const KdTree& tree, const Image& img, const std::vector<PacketHits16>& hits) {
    for (std::size_t p = 0; p < img.packets.size(); ++p)
        for (int i = 0; i < 16; ++i) {
            const Hit& want = img.want[p * 16 + std::size_t(i)];
            const Hit got = hits[p].hit(i);
            if (want.triangle == got.triangle && want.t == got.t && want.u == got.u && want.v == got.v) continue;
            const ::testing::AssertionResult r = same_hit(tree, img.packets[p].ray(i), got);
            if (!r) return ::testing::AssertionFailure() << "packet " << p << " lane " << i << ": " << r.message();
        }
    return ::testing::AssertionSuccess();
}

// The tiles must partition the grid, never cross an initial tile, and report their entry point's
// subtree size (0 for tiles whose beam misses everything); divergent tiles only at the minimum size.
::testing::AssertionResult tiles_partition(const std::vector<TileInfo>& tiles, const PacketGrid& grid,
                                           const MlrtaSettings& s, const std::vector<std::uint32_t>& subtree) {
    std::vector<int> cover(std::size_t(grid.columns) * std::size_t(grid.rows), 0);
    const int side = s.initial_tile / 4, min_side = s.min_tile / 4;
    for (const TileInfo& t : tiles) {
        if (t.x0 < 0 || t.y0 < 0 || t.x1 > grid.columns || t.y1 > grid.rows || t.x0 >= t.x1 || t.y0 >= t.y1)
            return ::testing::AssertionFailure() << "tile out of the grid or empty";
        if (t.x0 / side != (t.x1 - 1) / side || t.y0 / side != (t.y1 - 1) / side)
            return ::testing::AssertionFailure() << "tile crosses an initial tile";
        if (t.entry_node >= subtree.size()) return ::testing::AssertionFailure() << "entry node out of the tree";
        if (t.subtree_nodes != 0 && t.subtree_nodes != subtree[t.entry_node])
            return ::testing::AssertionFailure() << "subtree size of node " << t.entry_node;
        if (t.divergent && (t.x1 - t.x0 > min_side || t.y1 - t.y0 > min_side))
            return ::testing::AssertionFailure() << "divergent tile above the minimum size";
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) ++cover[std::size_t(y) * std::size_t(grid.columns) + std::size_t(x)];
    }
    for (std::size_t i = 0; i < cover.size(); ++i)
        if (cover[i] != 1) return ::testing::AssertionFailure() << "packet " << i << " traced " << cover[i] << " times";
    return ::testing::AssertionSuccess();
}

// Every tile bigger than the minimum size has a leaf entry point or sees nothing (the paper's rule,
// without the stuck-tile shortcut).
::testing::AssertionResult split_until_leaf(const std::vector<TileInfo>& tiles, const KdTree& tree,
                                            const MlrtaSettings& s) {
    const int min_side = s.min_tile / 4;
    for (const TileInfo& t : tiles) {
        if (t.x1 - t.x0 <= min_side && t.y1 - t.y0 <= min_side) continue;
        if (t.subtree_nodes != 0 && !detail::Access::impl(tree).nodes[t.entry_node].is_leaf())
            return ::testing::AssertionFailure() << "tile " << t.x0 << "," << t.y0 << " - " << t.x1 << "," << t.y1
                                                 << " not split though its entry point " << t.entry_node << " is inner";
    }
    return ::testing::AssertionSuccess();
}

// Runs every setting; counts in covered_entries the tiles (over all runs) whose entry point is a
// covered flat leaf.
void run_every_setting(const KdTree& tree, const Image& img, int& covered_entries) {
    const std::vector<std::uint32_t> subtree = subtree_sizes(detail::Access::impl(tree));
    const std::vector<std::uint8_t> covered = covered_flat_leaves(detail::Access::impl(tree));
    int runs = 0;
    covered_entries = 0;
    for (int sf : {4, 16})
        for (int its : {16, 32, 64, 128})
            for (int mts : {4, 8, 16, 32}) {
                if (mts > its) continue;
                for (FrustumTest ft : {FrustumTest::inverse, FrustumTest::direct})
                    for (EpSearch order : {EpSearch::bifurcation_stack, EpSearch::top_down})
                        for (bool stuck : {false, true})
                            for (int threads : {1, 2}) {
                                MlrtaSettings s;
                                s.split_factor = sf;
                                s.initial_tile = its;
                                s.min_tile = mts;
                                s.experimental.frustum_test = ft;
                                s.experimental.ep_search = order;
                                s.experimental.stop_when_stuck = stuck;
                                s.experimental.triangle_culling =
                                    (threads == 2) != stuck;  // mixed in, not a full product
                                s.experimental.ep_resume = (threads == 1) != (order == EpSearch::top_down);
                                s.experimental.retry_stuck = (sf == 16) != (ft == FrustumTest::direct);
                                // 1, 2 or 4 packets per side traced together, mixed in
                                s.experimental.xp_packets = 1 << ((its / 16 + mts / 4 + threads + int(order)) % 3);
                                const Mlrta mlrta(tree, s);
                                std::vector<PacketHits16> hits(img.packets.size());
                                std::vector<TileInfo> tiles;
                                std::mutex lock;
                                const TileObserver observe = [&](const TileInfo& t) {
                                    const std::lock_guard<std::mutex> guard(lock);
                                    tiles.push_back(t);
                                };
                                QueryCounters counters;
                                mlrta.intersect(img.grid, hits, QueryOptions{threads, &counters}, observe);
                                const std::string where = "SF " + std::to_string(sf) + " ITS " + std::to_string(its) +
                                                          " MTS " + std::to_string(mts) + " direct " +
                                                          std::to_string(ft == FrustumTest::direct) + " order " +
                                                          std::to_string(int(order)) + " stuck " +
                                                          std::to_string(stuck) + " threads " + std::to_string(threads) +
                                                          " xp " + std::to_string(s.experimental.xp_packets);
                                ASSERT_TRUE(same_as_kd(tree, img, hits)) << where;
                                ASSERT_TRUE(tiles_partition(tiles, img.grid, s, subtree)) << where;
                                for (const TileInfo& t : tiles)
                                    covered_entries += t.subtree_nodes != 0 && covered[t.entry_node];
                                if (!stuck) {
                                    ASSERT_TRUE(split_until_leaf(tiles, tree, s)) << where;
                                }
                                ASSERT_EQ(counters.mlrta.tiles, tiles.size()) << where;
                                ASSERT_EQ(counters.packets, img.packets.size()) << where;

                                const PacketGrid short_grid{img.short_packets.data(), img.grid.columns, img.grid.rows};
                                std::vector<std::uint32_t> occluded(img.packets.size(), 0xDEADBEEFu);
                                mlrta.occluded(short_grid, occluded, QueryOptions{threads, nullptr});
                                for (std::size_t p = 0; p < occluded.size(); ++p)
                                    for (int i = 0; i < 16; ++i) {
                                        if (!(((occluded[p] ^ img.shade[p]) >> i) & 1u)) continue;
                                        ASSERT_TRUE(
                                            same_occlusion(tree, img.short_packets[p].ray(i), (occluded[p] >> i) & 1u))
                                            << where << " packet " << p << " lane " << i;
                                    }
                                ++runs;
                            }
            }
    EXPECT_EQ(runs, 15 * 2 * 2 * 2 * 2 * 2);
}

// A room of boxes on an integer grid (flat, covered leaves) and a soup of triangles. Built with the
// SAH's textbook test cost (1.5, the default before 2026-12-04): with the default's cheaper tests the
// walls' cells keep the soup's triangles, and no leaf is flat and covered, so termination (4) would
// not be exercised.
const KdTree& room() {
    static const KdTree tree = [] {
        KdBuildRules rules;
        rules.intersection_cost = 1.5f;
        return KdTree::build(box_room(30, 51), rules);
    }();
    return tree;
}

}  // namespace

TEST(MlrtaTileSplitter, CameraInsideARoomEqualsKdTreeForEverySetting) {
    // 100 x 76 pixels: 25 x 19 packets, not a multiple of any tile size.
    const Image img(room(),
                    {{1.3f, 0.6f, 2.7f}, {0.3f, 1.0f, -0.35f}, {0.01f, -0.003f, 0}, {0, 0.0035f, 0.01f}, 100, 76});
    int covered_entries = 0;
    run_every_setting(room(), img, covered_entries);
    EXPECT_GT(covered_entries, 0) << "tiles looking at a wall stop at its flat, covered leaf (termination (4))";
}

TEST(MlrtaTileSplitter, CameraOutsideASoupEqualsKdTreeForEverySetting) {
    static const KdTree soup = KdTree::build(random_soup(4000, 52));
    // Looking along -z at the soup: the view centre changes sign in x and y (divergent tiles), and
    // rays around the soup hit nothing (entry points that miss).
    int covered_entries = 0;
    run_every_setting(soup, Image(soup, {{0.5f, 0.5f, 3.0f}, {0, 0, -1.0f}, {0.0075f, 0, 0}, {0, 0.0075f, 0}, 96, 80}),
                      covered_entries);
}

TEST(MlrtaTileSplitter, ResumedSearchesAndTraversalsGiveTheSameAnswersInFewerSteps) {
    // Entry-point searches of sub-tiles and interval traversal of packets start at the first
    // potential leaf of their tile's search (ep_resume): the same hits bit for bit and the same
    // occlusion bits as without, in fewer steps, for the paper's schedule, the stuck rule and its
    // retry, and both search orders.
    static const KdTree tree = KdTree::build(random_soup(20000, 53, 0.03f));
    const Image img(tree, {{0.5f, 0.45f, 2.5f}, {0.02f, 0.03f, -1.0f}, {0.0035f, 0, 0}, {0, 0.0035f, 0}, 128, 128});
    const PacketGrid short_grid{img.short_packets.data(), img.grid.columns, img.grid.rows};
    for (int stuck = 0; stuck < 3; ++stuck)  // the paper's schedule, stop when stuck, retry once
        for (EpSearch order : {EpSearch::bifurcation_stack, EpSearch::top_down}) {
            MlrtaSettings s;
            s.initial_tile = 64;
            s.experimental.stop_when_stuck = stuck > 0;
            s.experimental.retry_stuck = stuck == 2;
            s.experimental.ep_search = order;
            std::vector<PacketHits16> hits[2];
            std::vector<std::uint32_t> occluded[2];
            QueryCounters counters[2];
            for (int resume = 0; resume < 2; ++resume) {
                s.experimental.ep_resume = resume == 1;
                const Mlrta mlrta(tree, s);
                hits[resume].resize(img.packets.size());
                occluded[resume].assign(img.packets.size(), 0u);
                mlrta.intersect(img.grid, hits[resume], QueryOptions{1, &counters[resume]});
                mlrta.occluded(short_grid, occluded[resume]);
            }
            const std::string where = "stuck " + std::to_string(stuck) + " order " + std::to_string(int(order));
            ASSERT_TRUE(same_as_kd(tree, img, hits[1])) << where;
            for (std::size_t p = 0; p < img.packets.size(); ++p) {
                ASSERT_EQ(occluded[0][p], occluded[1][p]) << where << " packet " << p;
                for (int i = 0; i < 16; ++i) {
                    ASSERT_EQ(hits[0][p].triangle[i], hits[1][p].triangle[i]) << where << " packet " << p;
                    ASSERT_EQ(hits[0][p].t[i], hits[1][p].t[i]) << where << " packet " << p;
                    ASSERT_EQ(hits[0][p].u[i], hits[1][p].u[i]) << where << " packet " << p;
                    ASSERT_EQ(hits[0][p].v[i], hits[1][p].v[i]) << where << " packet " << p;
                }
            }
            // Searches may take a few more steps here (a soup seen from outside: short walks to the
            // first potential leaf, which the trail's tests cost as much as); traversal takes fewer,
            // and so do both together.
            EXPECT_LT(counters[1].packet_steps, counters[0].packet_steps) << where;
            EXPECT_LT(counters[1].packet_steps + counters[1].mlrta.ep_steps,
                      counters[0].packet_steps + counters[0].mlrta.ep_steps)
                << where;
            EXPECT_LE(counters[1].triangle_tests, counters[0].triangle_tests) << where;
        }
}

// Blocks of 2x2 and 4x4 packets traced by one interval traversal (xp_packets) on `tree` and `img`:
// the same closest hits as the kd-tree's single rays, the same occlusion bits as packets alone.
// Returns the packet steps of xp 1, 2, 4.
std::vector<std::uint64_t> trace_together(const KdTree& tree, const Image& img) {
    const PacketGrid short_grid{img.short_packets.data(), img.grid.columns, img.grid.rows};
    std::vector<std::uint32_t> alone;
    std::vector<std::uint64_t> steps;
    for (int xp : {1, 2, 4}) {
        MlrtaSettings s;
        s.initial_tile = 64;
        s.min_tile = 16;  // tiles of 4x4 packets at least: every block is whole where the image allows
        s.experimental.xp_packets = xp;
        const Mlrta mlrta(tree, s);
        std::vector<PacketHits16> hits(img.packets.size());
        std::vector<std::uint32_t> occluded(img.packets.size(), 0xDEADBEEFu);
        QueryCounters counters;
        mlrta.intersect(img.grid, hits, QueryOptions{1, &counters});
        mlrta.occluded(short_grid, occluded);
        const std::string where = "xp " + std::to_string(xp);
        EXPECT_TRUE(same_as_kd(tree, img, hits)) << where;
        EXPECT_EQ(counters.packets, img.packets.size()) << where;
        if (xp == 1) alone = occluded;
        EXPECT_EQ(occluded, alone) << where;
        steps.push_back(counters.packet_steps);
    }
    return steps;
}

TEST(MlrtaTileSplitter, PacketsTracedTogetherGiveTheSameAnswers) {
    // In a room of boxes (large faces: the blocks' intervals stay tight) the inner-node steps per
    // packet fall; in a soup of small triangles seen from outside they need not (the answers are
    // the same either way).
    // (pixels 0.002 apart: a block of 4x4 packets spans about 2 degrees, within interval traversal's
    // limit of about 3)
    const Image inside(room(),
                       {{1.3f, 0.6f, 2.7f}, {0.3f, 1.0f, -0.35f}, {0.002f, -0.0006f, 0}, {0, 0.0007f, 0.002f}, 128, 96});
    const std::vector<std::uint64_t> steps = trace_together(room(), inside);
    EXPECT_LT(double(steps[1]), 0.8 * double(steps[0]));
    EXPECT_LT(steps[2], steps[1]);
    static const KdTree soup = KdTree::build(random_soup(20000, 54, 0.03f));
    trace_together(soup, Image(soup, {{0.5f, 0.45f, 2.5f}, {0.02f, 0.03f, -1.0f}, {0.0035f, 0, 0}, {0, 0.0035f, 0}, 128, 120}));
    MlrtaSettings bad;
    bad.experimental.xp_packets = 3;
    EXPECT_THROW(Mlrta(soup, bad), Error);
}

TEST(MlrtaTileSplitter, ZeroComponentsAndInactiveRaysEqualKdTree) {
    const KdTree& tree = room();
    Image img(tree, {{4.5f, 0.5f, 1.5f}, {0.0f, 1.0f, 0.0f}, {0.01f, 0, 0}, {0, 0, 0.01f}, 64, 64});
    // A row and a column of pixels with exact +-0 components; some packets partly or wholly inactive.
    for (std::size_t p = 0; p < img.packets.size(); ++p) {
        Packet16& packet = img.packets[p];
        for (int i = 0; i < 16; ++i) {
            if (i % 4 == 1) packet.dir_x[i] = p % 2 ? 0.0f : -0.0f;
            if (i / 4 == 2) packet.dir_z[i] = p % 3 ? -0.0f : 0.0f;
            img.want[p * 16 + std::size_t(i)] = tree.intersect(packet.ray(i));
        }
        if (p % 5 == 0) packet.active = 0x0F0Fu;
        if (p % 11 == 0) packet.active = 0;
        for (int i = 0; i < 16; ++i)
            if (!((packet.active >> i) & 1u)) img.want[p * 16 + std::size_t(i)] = Hit{};
    }
    for (int xp : {1, 2, 4})  // packets alone, and blocks of packets traced together
        for (int threads : {1, 2}) {
            MlrtaSettings s;
            s.experimental.xp_packets = xp;
            s.min_tile = 4 * xp;
            const Mlrta mlrta(tree, s);
            std::vector<PacketHits16> hits(img.packets.size());
            QueryCounters counters;
            mlrta.intersect(img.grid, hits, QueryOptions{threads, &counters});
            EXPECT_TRUE(same_as_kd(tree, img, hits)) << "threads " << threads << " xp " << xp;
            EXPECT_GT(counters.single_rays, 0u);
            EXPECT_EQ(counters.packets, img.packets.size());
        }
}

// A camera looking along a diagonal: every ray has the same direction signs, but the dominant axis
// changes between packets 9 and 10 of each row (x - y = 0.01 * (sx - 5.5)). No tile diverges in sign,
// so none may be counted, reported or treated as divergent (divergent tiles get no entry point).
TEST(MlrtaTileSplitter, DivergentOnlyWhenSignsDiffer) {
    const KdTree& tree = room();
    const Camera cam{
        {0.5f, 0.5f, 3.5f}, {1.0f, 1.055f, -0.3f}, {0.005f, -0.005f, 0}, {-0.0012f, -0.0012f, 0.008f}, 64, 64};
    Image img(tree, cam);
    for (const Packet16& p : img.packets)
        for (int i = 0; i < 16; ++i) ASSERT_TRUE(p.dir_x[i] > 0 && p.dir_y[i] > 0 && p.dir_z[i] < 0);
    MlrtaSettings small_tiles;
    small_tiles.initial_tile = 64;
    small_tiles.min_tile = 16;
    for (const MlrtaSettings& s : {MlrtaSettings{}, small_tiles}) {
        const Mlrta mlrta(tree, s);
        std::vector<PacketHits16> hits(img.packets.size());
        std::vector<TileInfo> tiles;
        QueryCounters counters;
        mlrta.intersect(img.grid, hits, QueryOptions{1, &counters}, [&](const TileInfo& t) { tiles.push_back(t); });
        ASSERT_TRUE(same_as_kd(tree, img, hits));
        EXPECT_EQ(counters.mlrta.divergent_tiles, 0u) << "ITS " << s.initial_tile << " MTS " << s.min_tile;
        int divergent = 0;
        for (const TileInfo& t : tiles) divergent += t.divergent;
        EXPECT_EQ(divergent, 0) << "of " << tiles.size() << " tiles, ITS " << s.initial_tile << " MTS " << s.min_tile;
    }
}

TEST(MlrtaTileSplitter, SettingsValidationNamesTheSetting) {
    EXPECT_NO_THROW(MlrtaSettings{}.validate());
    auto message = [](const MlrtaSettings& s) -> std::string {
        try {
            s.validate();
        } catch (const Error& e) {
            return e.what();
        }
        return "no error";
    };
    for (int bad : {0, 2, 6, 130, 8192}) {
        MlrtaSettings s;
        s.initial_tile = bad;
        s.min_tile = 4;
        EXPECT_NE(message(s).find("initial_tile"), std::string::npos) << bad << ": " << message(s);
    }
    for (int bad : {0, 2, 6, 256}) {
        MlrtaSettings s;
        s.min_tile = bad;
        EXPECT_NE(message(s).find("min_tile"), std::string::npos) << bad << ": " << message(s);
    }
    for (int bad : {0, 2, 8, 64}) {
        MlrtaSettings s;
        s.split_factor = bad;
        EXPECT_NE(message(s).find("split_factor"), std::string::npos) << bad << ": " << message(s);
    }
    MlrtaSettings bad;
    bad.split_factor = 9;
    EXPECT_THROW(Mlrta(room(), bad), Error);

    const Mlrta mlrta(room());
    std::vector<Packet16> packets(4);
    std::vector<PacketHits16> hits(4);
    try {
        mlrta.intersect(PacketGrid{packets.data(), 2, 2}, hits, QueryOptions{0, nullptr});
        ADD_FAILURE() << "threads = 0 accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("threads"), std::string::npos) << e.what();
    }
    EXPECT_THROW(mlrta.intersect(PacketGrid{packets.data(), -1, 2}, hits), Error);
    EXPECT_THROW(mlrta.intersect(PacketGrid{nullptr, 2, 2}, hits), Error);
    // One answer per packet of the grid: a span of another size is refused, naming the sizes.
    try {
        mlrta.intersect(PacketGrid{packets.data(), 2, 1}, hits);
        ADD_FAILURE() << "4 answers accepted for 2 packets";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("2 inputs but room for 4"), std::string::npos) << e.what();
    }
}
