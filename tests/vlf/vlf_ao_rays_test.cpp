// AO rays along the PSF directions (section 7, `--ao-dirs psf`): every ray runs exactly along a
// direction of the set (either way), inside the normal's hemisphere, and the default stratified
// random rays are unchanged (bit for bit).
#include <gtest/gtest.h>

#include <bit>
#include <map>
#include <set>

#include "beamtrace/error.hpp"
#include "beamtrace/vlf.hpp"
#include "experiments/bench_run.hpp"

using namespace beamtrace;
using namespace beamtrace::workload;

namespace {

// FNV-1a over the bits of every active ray.
std::uint64_t fingerprint(const RaySet& rays) {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&](float f) {
        std::uint32_t b = std::bit_cast<std::uint32_t>(f);
        for (int k = 0; k < 4; ++k, b >>= 8) h = (h ^ (b & 0xFFu)) * 1099511628211ull;
    };
    for (std::size_t slot = 0; slot < rays.slots(); ++slot) {
        if (!rays.active(slot)) continue;
        const Ray r = rays.ray(slot);
        for (float f : {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tnear, r.tfar}) mix(f);
    }
    return h;
}

WorkloadConfig ao_config(AoDirections dirs) {
    WorkloadConfig config;
    config.scene = "tetra:3";
    config.width = config.height = 32;
    config.mode = Mode::ao;
    config.ao_rays = 16;
    config.ao_directions = dirs;
    return config;
}

}  // namespace

TEST(VlfAoRays, RandomDirectionsAreUnchanged) {
    // The fingerprint of the rays make_ao_rays produced before it learnt about PSF directions
    // (computed with tools/workload/ray_set.cpp of commit 6fd37c6). Primary hits come from the kd-tree, whose answers
    // are the same on every machine and instruction set (Embree's last bits may differ between them).
    const scenes::SceneSource source = scenes::load_scene("tetra:3");
    const RaySet primary = make_primary_rays(source.camera, 32, 32);
    const KdTree tree = KdTree::build(source.scene);
    std::vector<Hit> hits(primary.slots());
    for (std::size_t slot = 0; slot < primary.slots(); ++slot)
        if (primary.active(slot)) hits[slot] = tree.intersect(primary.ray(slot));
    EXPECT_EQ(fingerprint(make_ao_rays(source.scene, primary, hits, 16)), 0x60941a7cd189b3a3ull);
    EXPECT_EQ(fingerprint(make_ao_rays(source.scene, primary, hits, 16, AoDirections{})), 0x60941a7cd189b3a3ull);
}

TEST(VlfAoRays, PsfDirectionsLieAlongTheSetInsideTheHemisphere) {
    for (int count : {33, 513}) {
        const Workload w = make_workload(ao_config(AoDirections{AoDirections::Source::psf, count}));
        const Workload random = make_workload(ao_config(AoDirections{}));
        ASSERT_EQ(w.rays.ray_count, random.rays.ray_count);
        const DirectionSet set(count);
        std::map<std::uint32_t, std::size_t> primary_slot;  // pixel -> its primary ray
        for (std::size_t slot = 0; slot < w.primary.slots(); ++slot)
            if (w.primary.active(slot)) primary_slot[w.primary.pixel[slot]] = slot;
        std::set<std::uint32_t> used;
        for (std::size_t slot = 0; slot < w.rays.slots(); ++slot) {
            if (!w.rays.active(slot)) continue;
            const Ray r = w.rays.ray(slot), base = random.rays.ray(slot);
            EXPECT_EQ(r.org, base.org);
            EXPECT_EQ(r.tfar, base.tfar);
            const DirectionSet::Nearest n = set.nearest(r.dir);
            const Float3 d = set.direction(int(n.index)) * (n.reversed ? -1.0f : 1.0f);
            ASSERT_EQ(r.dir, d) << "slot " << slot << ": not exactly a set direction";
            used.insert(n.index);
            // Inside the hemisphere of the surface normal at the origin.
            const std::size_t p = primary_slot.at(w.rays.pixel[slot]);
            const SurfacePoint s = surface_point(w.source.scene, w.primary.ray(p), w.primary_hits[p]);
            EXPECT_GT(dot(r.dir, s.normal), 0.0f) << "slot " << slot;
        }
        EXPECT_GT(used.size(), std::size_t(count) / 3) << "the rays spread over the set";
    }
    EXPECT_THROW(make_workload(ao_config(AoDirections{AoDirections::Source::psf, 100})), Error);
    EXPECT_EQ(parse_ao_directions("psf"), AoDirections::Source::psf);
    EXPECT_THROW(parse_ao_directions("uniform"), Error);
}
