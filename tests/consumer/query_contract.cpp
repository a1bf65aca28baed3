// The query contract as a user sees it, through the installed package only: the six calls on KdTree,
// Mlrta and VisibilityField with threads = 2 must give the hits of single-ray KdTree::intersect on
// 100,000 random rays (and its occlusion answers), and bad spans must be refused with an Error.
// Exits non-zero on any difference.
#include <beamtrace/beamtrace.hpp>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace bt = beamtrace;

namespace {

constexpr std::size_t kRays = 100000;
int failures = 0;

void fail(const std::string& what) {
    if (++failures <= 20) std::printf("FAIL: %s\n", what.c_str());
}

// A soup of small random triangles in the unit cube.
bt::Scene random_scene(std::mt19937& rng, int triangles) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f), d(-0.04f, 0.04f);
    std::vector<float> xyz;
    std::vector<std::uint32_t> idx;
    for (int t = 0; t < triangles; ++t) {
        const float cx = u(rng), cy = u(rng), cz = u(rng);
        for (int k = 0; k < 3; ++k) {
            xyz.insert(xyz.end(), {cx + d(rng), cy + d(rng), cz + d(rng)});
            idx.push_back(std::uint32_t(idx.size()));
        }
    }
    return bt::Scene(xyz.data(), xyz.size() / 3, idx.data(), idx.size() / 3);
}

// Rays from around the cube in every direction; a third of them end early (finite tfar).
std::vector<bt::Ray> random_rays(std::mt19937& rng) {
    std::uniform_real_distribution<float> o(-0.3f, 1.3f), s(-1.0f, 1.0f), len(0.1f, 1.5f);
    std::vector<bt::Ray> rays(kRays);
    for (std::size_t i = 0; i < kRays; ++i) {
        bt::Ray& r = rays[i];
        r.org = {o(rng), o(rng), o(rng)};
        r.dir = {s(rng), s(rng), s(rng)};
        r.tnear = 0.0f;
        r.tfar = i % 3 == 0 ? len(rng) : bt::kInfinity;
    }
    return rays;
}

std::vector<bt::Packet16> as_packets(const std::vector<bt::Ray>& rays) {
    std::vector<bt::Packet16> packets((rays.size() + 15) / 16);
    for (std::size_t p = 0; p < packets.size(); ++p) {
        packets[p].active = 0;
        for (int i = 0; i < 16; ++i) {
            const std::size_t k = p * 16 + std::size_t(i);
            packets[p].set_ray(i, rays[k < rays.size() ? k : rays.size() - 1]);
            if (k < rays.size()) packets[p].active |= 1u << i;
        }
    }
    return packets;
}

// Same hit: the same t and triangle (another triangle at exactly the same t is a tie, counted).
int ties = 0;
void expect_hit(const std::string& who, std::size_t i, const bt::Hit& got, const bt::Hit& want) {
    if (got.t == want.t && got.triangle == want.triangle) return;
    if (got.hit() && want.hit() && got.t == want.t) {
        ++ties;
        return;
    }
    fail(who + " ray " + std::to_string(i) + ": triangle " + std::to_string(got.triangle) + " t " +
         std::to_string(got.t) + ", want triangle " + std::to_string(want.triangle) + " t " + std::to_string(want.t));
}

template <class Accelerator>
void check(const std::string& name, const Accelerator& a, const std::vector<bt::Ray>& rays,
           const std::vector<bt::Hit>& want, const std::vector<std::uint8_t>& want_occluded) {
    const bt::QueryOptions two{2, nullptr};
    const std::vector<bt::Packet16> packets = as_packets(rays);
    // 1, 2: single rays.
    for (std::size_t i = 0; i < rays.size(); i += 7) {
        expect_hit(name + " intersect(Ray)", i, a.intersect(rays[i]), want[i]);
        if (a.occluded(rays[i]) != (want_occluded[i] != 0)) fail(name + " occluded(Ray) ray " + std::to_string(i));
    }
    // 3, 4: spans of rays.
    std::vector<bt::Hit> hits(rays.size());
    std::vector<std::uint8_t> occluded(rays.size(), 2);
    a.intersect(rays, hits, two);
    a.occluded(rays, occluded, two);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        expect_hit(name + " intersect(span<Ray>)", i, hits[i], want[i]);
        if (occluded[i] != want_occluded[i]) fail(name + " occluded(span<Ray>) ray " + std::to_string(i));
    }
    // 5, 6: spans of packets.
    std::vector<bt::PacketHits16> packet_hits(packets.size());
    std::vector<std::uint32_t> bits(packets.size(), 0xDEADBEEFu);
    a.intersect(packets, packet_hits, two);
    a.occluded(packets, bits, two);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        expect_hit(name + " intersect(span<Packet16>)", i, packet_hits[i / 16].hit(int(i % 16)), want[i]);
        if (((bits[i / 16] >> (i % 16)) & 1u) != want_occluded[i])
            fail(name + " occluded(span<Packet16>) ray " + std::to_string(i));
    }
    if (bits.back() >> (rays.size() % 16 == 0 ? 16 : rays.size() % 16)) fail(name + ": an inactive lane is occluded");
    // Spans of different sizes and threads < 1 are refused, naming the problem.
    try {
        a.intersect(rays, std::span<bt::Hit>(hits.data(), hits.size() - 1));
        fail(name + ": a short answer span was accepted");
    } catch (const bt::Error& e) {
        if (std::string(e.what()).find("same size") == std::string::npos) fail(name + ": message " + e.what());
    }
    try {
        a.occluded(packets, bits, bt::QueryOptions{0, nullptr});
        fail(name + ": threads = 0 was accepted");
    } catch (const bt::Error&) {}
    // Counters count.
    bt::QueryCounters counters;
    a.intersect(std::span<const bt::Packet16>(packets.data(), 64), std::span<bt::PacketHits16>(packet_hits.data(), 64),
                bt::QueryOptions{2, &counters});
    // Packets (kd-tree, MLRTA) or rays (the field counts ray by ray); the lanes of these incoherent
    // packets go alone (single_rays) or are tested as packets (triangle_tests).
    if (counters.packets + counters.rays == 0) fail(name + ": the counters counted nothing traced");
    if (counters.triangle_tests + counters.single_rays == 0) fail(name + ": the counters counted no work");
    std::printf("%s: the six calls agree with single-ray KdTree::intersect on %zu rays\n", name.c_str(), rays.size());
}

}  // namespace

int main() {
    std::mt19937 rng(2026);
    const bt::Scene scene = random_scene(rng, 20000);
    const std::vector<bt::Ray> rays = random_rays(rng);
    const bt::KdTree tree = bt::KdTree::build(scene);
    std::vector<bt::Hit> want(rays.size());
    std::vector<std::uint8_t> want_occluded(rays.size());
    std::size_t hit = 0, blocked = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        want[i] = tree.intersect(rays[i]);
        want_occluded[i] = tree.occluded(rays[i]) ? 1 : 0;
        if (want_occluded[i] != (want[i].hit() ? 1 : 0))
            fail("KdTree::occluded and intersect disagree on ray " + std::to_string(i));
        hit += want[i].hit();
        blocked += want_occluded[i];
    }
    std::printf("%zu rays: %zu hit, %zu occluded\n", rays.size(), hit, blocked);
    if (hit < rays.size() / 10 || hit > rays.size() * 9 / 10)
        fail("the rays do not test much (too few or too many hits)");

    check("KdTree", tree, rays, want, want_occluded);
    check("Mlrta", bt::Mlrta(tree), rays, want, want_occluded);
    bt::VlfOptions vlf;
    vlf.directions = 129;
    vlf.tiles = 64;
    check("VisibilityField", bt::VisibilityField(scene, vlf), rays, want, want_occluded);
    std::printf("ties (same t, another triangle): %d\n", ties);
    if (failures) std::printf("%d failures\n", failures);
    return failures == 0 ? 0 : 1;
}
