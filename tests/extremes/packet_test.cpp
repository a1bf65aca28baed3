// Robust.Packet*: odd 4x4 packets through every packet entry point (kd16: Mlrta::intersect_packet
// and occluded_packet; mlrta: grids of tiles; vlf: packets and PSF-binned spans). Mixed direction
// signs inside one packet, one active ray, no active ray, garbage (NaN, infinities) in inactive
// lanes, and ill-formed rays in active lanes. The answer of every well-formed ray must be exactly
// what the same engine answers without the odd lanes; ill-formed and inactive lanes report nothing.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>

#include "extremes/engine_checks.hpp"
#include "extremes/exact_reference.hpp"
#include "rays/ray_set.hpp"

namespace beamtrace::test {
namespace {

using workload::Mode;
using workload::RaySet;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

EngineChoice fields(const Scene& scene) {
    EngineChoice choice;
    choice.brute = scene.triangle_count() <= 5000;
    choice.options.vlf.directions = 129;
    choice.options.vlf.tiles = 32;
    return choice;
}

// Rays that describe no segment, to put into lanes.
std::vector<Ray> poison(const Box& b) {
    const Float3 o = b.center();
    const float inf = kInfinity;
    return {{{kNaN, o.y, o.z}, 0.0f, {0, 0, 1}, inf},
            {o, 0.0f, {kNaN, 1, 1}, inf},
            {o, kNaN, {1, 0, 0}, inf},
            {o, 0.0f, {1, 1, 1}, kNaN},
            {{inf, o.y, o.z}, 0.0f, {-1, 0, 0}, inf},
            {o, 0.0f, {-inf, 1, 1}, inf},
            {o, 0.0f, {0, 0, 0}, inf},
            {o, 2.0f, {0, 1, 0}, 1.0f},
            {o, -inf, {0, 1, 0}, inf}};
}

// Answers of an engine for a set: hits (primary) or occlusion bits (otherwise), one per slot.
struct Answers {
    std::vector<Hit> hits;
    std::vector<std::uint8_t> occluded;
};

Answers answer(const EngineUnderTest& e, const RaySet& set) {
    Answers a;
    if (closest_hit(set.mode))
        e.engine->intersect(set, a.hits, 1);
    else
        e.engine->occluded(set, a.occluded, 1);
    return a;
}

bool same(const Hit& a, const Hit& b) {
    return a.triangle == b.triangle && (a.triangle == kNoHit || std::memcmp(&a.t, &b.t, sizeof(float)) == 0);
}

// For every engine: the altered set's answers equal the clean set's on the slots `kept` says (same
// slot in both), and report nothing on the others.
void expect_same_answers(const std::vector<EngineUnderTest>& engines, const RaySet& clean, const RaySet& altered,
                         const std::vector<std::uint8_t>& kept, const std::string& what) {
    for (const EngineUnderTest& e : engines) {
        const Answers a = answer(e, clean), b = answer(e, altered);
        std::size_t differ = 0, reported = 0, compared = 0;
        for (std::size_t slot = 0; slot < clean.slots(); ++slot) {
            const bool closest = closest_hit(clean.mode);
            if (kept[slot]) {
                if (!clean.active(slot)) continue;
                ++compared;
                differ += closest ? !same(a.hits[slot], b.hits[slot]) : a.occluded[slot] != b.occluded[slot];
            } else {
                reported += closest ? b.hits[slot].hit() : b.occluded[slot] != 0;
            }
        }
        EXPECT_GT(compared, 0u) << what;
        EXPECT_EQ(differ, 0u) << what << ": " << e.name << " answers differently when odd lanes are present";
        EXPECT_EQ(reported, 0u) << what << ": " << e.name << " reports something for an odd lane";
    }
}

// The camera's rays (an image, so MLRTA traces tiles) of each mode for the scene.
std::vector<RaySet> camera_sets(const scenes::SceneSource& source) {
    std::vector<RaySet> sets;
    for (Mode mode : {Mode::primary, Mode::shadow, Mode::ao}) {
        workload::WorkloadConfig config;
        config.mode = mode;
        config.width = config.height = mode == Mode::ao ? 16 : 48;
        config.ao_rays = 4;
        sets.push_back(workload::make_workload(source, config).rays);
    }
    return sets;
}

std::vector<scenes::SceneSource> packet_scenes() {
    return {scenes::load_scene("sphereflake:1"), scenes::load_scene("random:20000")};
}

}  // namespace

TEST(Robust, PacketIllFormedRaysInActiveLanes) {
    for (const scenes::SceneSource& s : packet_scenes()) {
        const auto engines = build_engines(s.scene, fields(s.scene));
        const std::vector<Ray> bad = poison(s.scene.bounds());
        for (const RaySet& clean : camera_sets(s)) {
            RaySet altered = clean;
            std::vector<std::uint8_t> kept(clean.slots(), 1);
            for (std::size_t p = 0; p < altered.packets.size(); ++p)
                for (int lane : {int(p % 16), int((p * 7 + 3) % 16)}) {
                    altered.packets[p].set_ray(lane, bad[(p + std::size_t(lane)) % bad.size()]);
                    altered.packets[p].active |= 1u << lane;
                    kept[p * 16 + std::size_t(lane)] = 0;
                }
            expect_same_answers(engines, clean, altered, kept,
                                s.name + " ill-formed active lanes " + workload::to_string(clean.mode));
        }
    }
}

TEST(Robust, PacketGarbageInInactiveLanes) {
    for (const scenes::SceneSource& s : packet_scenes()) {
        const auto engines = build_engines(s.scene, fields(s.scene));
        const std::vector<Ray> bad = poison(s.scene.bounds());
        for (const RaySet& clean : camera_sets(s)) {
            RaySet altered = clean;
            std::vector<std::uint8_t> kept(clean.slots(), 1);
            for (std::size_t p = 0; p < altered.packets.size(); ++p)
                for (int lane = 0; lane < 16; ++lane)
                    if (!((altered.packets[p].active >> lane) & 1u) || lane == int(p % 16)) {
                        altered.packets[p].set_ray(lane, bad[(p + std::size_t(lane)) % bad.size()]);
                        altered.packets[p].active &= ~(1u << lane);
                        kept[p * 16 + std::size_t(lane)] = 0;
                    }
            expect_same_answers(engines, clean, altered, kept,
                                s.name + " garbage in inactive lanes " + workload::to_string(clean.mode));
        }
    }
}

TEST(Robust, PacketOneActiveRay) {
    for (const scenes::SceneSource& s : packet_scenes()) {
        const auto engines = build_engines(s.scene, fields(s.scene));
        for (const RaySet& clean : camera_sets(s)) {
            RaySet altered = clean;
            std::vector<std::uint8_t> kept(clean.slots(), 0);
            for (std::size_t p = 0; p < altered.packets.size(); ++p) {
                const int lane = int((p * 5) % 16);
                altered.packets[p].active &= 1u << lane;
                kept[p * 16 + std::size_t(lane)] = 1;
            }
            expect_same_answers(engines, clean, altered, kept,
                                s.name + " one active ray " + workload::to_string(clean.mode));
        }
    }
}

TEST(Robust, PacketNoActiveRay) {
    for (const scenes::SceneSource& s : packet_scenes()) {
        const auto engines = build_engines(s.scene, fields(s.scene));
        const std::vector<Ray> bad = poison(s.scene.bounds());
        for (RaySet set : camera_sets(s)) {
            for (std::size_t p = 0; p < set.packets.size(); ++p) {
                set.packets[p].active = 0;
                if (p % 2)  // half of them full of garbage
                    for (int lane = 0; lane < 16; ++lane)
                        set.packets[p].set_ray(lane, bad[std::size_t(lane) % bad.size()]);
            }
            for (const EngineUnderTest& e : engines) {
                const Answers a = answer(e, set);
                std::size_t reported = 0;
                for (std::size_t slot = 0; slot < set.slots(); ++slot)
                    reported += closest_hit(set.mode) ? a.hits[slot].hit() : a.occluded[slot] != 0;
                EXPECT_EQ(reported, 0u) << s.name << ": " << e.name << " reports hits for packets with no active ray";
            }
        }
    }
}

// Packets whose 16 rays point into different octants (and some share one, to form groups), from a
// common origin inside the scene and from scattered origins; against Embree and exact geometry.
TEST(Robust, PacketMixedDirectionSigns) {
    for (const scenes::SceneSource& s : packet_scenes()) {
        const auto engines = build_engines(s.scene, fields(s.scene));
        const Box& b = s.scene.bounds();
        std::mt19937 rng(17);
        std::normal_distribution<float> g;
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        std::vector<Ray> rays;
        for (int p = 0; p < 240; ++p) {  // 12 rows of 20 packets in the image below
            const Float3 origin = b.lower + Float3{u(rng) * b.extent().x, u(rng) * b.extent().y, u(rng) * b.extent().z};
            const Float3 base = normalize(Float3{g(rng), g(rng), g(rng)});
            for (int lane = 0; lane < 16; ++lane) {
                // Lane bits 0-2 flip the signs of the base direction's components; lanes 8-15 repeat
                // lanes 0-7 with a slight spread (so octant groups of two form).
                Float3 d = base;
                for (int k = 0; k < 3; ++k)
                    if ((lane >> k) & 1) d[k] = -d[k];
                if (lane >= 8) d = d + Float3{0.01f * g(rng), 0.01f * g(rng), 0.01f * g(rng)};
                const Float3 o = p % 2 ? origin : origin + Float3{0.01f * g(rng), 0.01f * g(rng), 0.01f * g(rng)};
                rays.push_back(Ray{o, 0.0f, d, kInfinity});
            }
        }
        for (Mode mode : {Mode::primary, Mode::shadow}) {
            std::vector<Ray> r = rays;
            if (mode == Mode::shadow)
                for (Ray& x : r) x.tfar = 0.3f * b.diagonal();
            // As packets in order, and as an image (16 rays of a packet = one 4x4 block).
            expect_exact_engines_clean(check_engines(engines, workload_for(s, ray_set(r, mode)),
                                                     s.name + " mixed signs " + workload::to_string(mode),
                                                     s.scene.triangle_count() < 10000));
            const int width = 80;  // 20 blocks across
            ASSERT_EQ(r.size() % (16 * 20), 0u);
            std::vector<Ray> image(r.size());
            for (std::size_t i = 0; i < r.size(); ++i) {
                const std::size_t block = i / 16, lane = i % 16;
                const std::size_t x = (block % 20) * 4 + lane % 4, y = (block / 20) * 4 + lane / 4;
                image[y * width + x] = r[i];
            }
            expect_exact_engines_clean(check_engines(engines, workload_for(s, image_ray_set(image, width, mode)),
                                                     s.name + " mixed signs image " + workload::to_string(mode),
                                                     s.scene.triangle_count() < 10000));
        }
    }
}

}  // namespace beamtrace::test
