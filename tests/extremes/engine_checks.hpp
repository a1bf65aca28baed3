#pragma once
// What every extremes case does: build each engine on a scene, trace the same rays with each, and
// sort every ray against the Embree oracle and against exact (double-precision) geometry.
//
// Exact engines (zero `mismatch` required): kd1, kd16, mlrta (grids of tiles when the rays form an
// image, single packets otherwise), vlf (mode exact), brute, crsh, rah, lists and lists-flat. vlf-fast is approximate: its
// tallies are printed, never asserted.
#include <memory>
#include <string>
#include <vector>

#include "oracle/comparison.hpp"
#include "engines/engine.hpp"
#include "rays/workload.hpp"

namespace beamtrace::test {

struct EngineUnderTest {
    std::string name;
    bool exact = true;
    std::unique_ptr<workload::Engine> engine;
};

struct EngineChoice {
    bool brute = true;  // only where the scene is small enough (the engine refuses > 100k triangles)
    bool vlf_fast = true;
    bool crsh = true;  // crsh and rah (one object: the scenes here carry no partition)
    bool lists = true;  // lists, and lists-flat where brute is chosen
    workload::EngineOptions options;
};

// kd1, kd16, mlrta, vlf, then brute, vlf-fast, crsh, rah, lists and lists-flat as chosen, each built
// for the scene.
std::vector<EngineUnderTest> build_engines(const Scene& scene, const EngineChoice& choice = {});

// Rays packed 16 to a packet in the given order (no image: MLRTA traces them packet by packet).
workload::RaySet ray_set(const std::vector<Ray>& rays, workload::Mode mode);
// Rays of a width x height image given row by row: 4x4 pixel blocks form the packets and the
// packets a grid, so that MLRTA traces them as tiles of beams. Pixels past the end are inactive.
workload::RaySet image_ray_set(const std::vector<Ray>& rays, int width, workload::Mode mode);
// Every active ray of a set, in slot order.
std::vector<Ray> rays_of(const workload::RaySet& set);

// A workload whose rays are `rays` (closest hit when closest_hit(mode), occlusion otherwise), with the
// oracle's answers; the scene comes from `source`.
workload::Workload workload_for(const scenes::SceneSource& source, workload::RaySet rays);

// A comparison: the oracle's four classes, plus the disagreements that a surface at an end of the
// segment explains. Hits exactly at tnear or tfar may be reported or not (the contract of
// beamtrace/ray.hpp and of Embree): a disagreement counts as `at_end` instead of `mismatch` when
// exact geometry finds a surface within the grazing distance of that end, and the answers agree
// once that end is moved past it.
struct Comparison {
    oracle::Tally tally;
    std::uint64_t at_end = 0;

    void record_hit(const Scene& scene, std::uint64_t index, const Ray& ray, const Hit& ours, const Hit& reference);
    void record_occlusion(const Scene& scene, std::uint64_t index, const Ray& ray, bool ours, bool reference);
    std::uint64_t total() const { return tally.total() + at_end; }
    std::string summary() const;
};

struct EngineReport {
    std::string engine;
    bool exact = true;
    Comparison oracle;    // against Embree
    Comparison geometry;  // against exact geometry (empty when not asked for)
};

struct CaseReport {
    std::string what;
    Comparison embree_vs_geometry;  // is Embree itself consistent here? (empty when not asked for)
    std::vector<EngineReport> engines;
};

// Traces the workload's rays with every engine and classifies each ray; with `geometry` also against
// exact geometry (brute force in double: keep the ray count times triangle count modest).
CaseReport check_engines(const std::vector<EngineUnderTest>& engines, const workload::Workload& workload,
                         const std::string& what, bool geometry);

// Prints one line per engine (kept in the test log; docs/robustness.md quotes them) and expects
// zero `mismatch` against exact geometry for every exact engine and, where Embree agrees with
// exact geometry (no mismatch of its own), zero against Embree too.
void expect_exact_engines_clean(const CaseReport& report);
void print(const CaseReport& report);

}  // namespace beamtrace::test
