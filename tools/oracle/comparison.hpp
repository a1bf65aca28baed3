#pragma once
// Sorting each ray of a comparison between our traversal and the Embree oracle into exactly one
// class, and counting the classes.
//
// Closest-hit rays:
//   agree     both miss, or both hit the same triangle with |dt| <= 1e-4 * max(1, t)
//   ties      both hit, different triangles, same t within that tolerance (shared edges, vertices)
//   grazing   any other disagreement where the ray segment [tnear, min(tfar, exit of the scene)]
//             passes within 1e-5 * (scene box diagonal) of an edge of a triangle either side hit;
//             or where one side misses and the other hit a triangle that the ray's line crosses
//             within that distance of an end of the segment (tnear or tfar: float t decides whether
//             such a crossing is in or out, and tracers round differently), while the line crosses
//             no triangle on the segment farther than that from both ends (double-precision brute
//             force over the scene)
//   mismatch  everything else
// Occlusion rays: agree if both answers are equal; otherwise grazing if the ray passes within that
// distance of an edge of the triangle the "occluded" side hit (triangle_hint, from a closest-hit
// query on the same ray; with kNoHit every non-degenerate triangle of the scene is a candidate, found
// by a double-precision brute-force search), or if its segment's ends explain the disagreement as
// above (a crossing within that distance of an end, of the hinted triangle when there is a hint,
// and none on the segment away from the ends); otherwise mismatch.
//
// A reported hit on a degenerate triangle or on an id outside the scene is always a mismatch (no
// query may ever hit those).
#include <cstdint>
#include <string>
#include <vector>

#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"

namespace beamtrace::oracle {

enum class Verdict { agree, ties, grazing, mismatch };

// "agree", "ties", "grazing", "mismatch".
const char* to_string(Verdict verdict);

Verdict classify_hit(const Scene& scene, const Ray& ray, const Hit& ours, const Hit& oracle);
Verdict classify_occlusion(const Scene& scene, const Ray& ray, bool ours, bool oracle,
                           std::uint32_t triangle_hint = kNoHit);

// One disagreement kept for the report.
struct Example {
    std::uint64_t ray_index = 0;
    Ray ray;
    bool occlusion = false;  // occlusion ray: the answers are ours_occluded / oracle_occluded
    Hit ours, oracle;        // closest-hit ray: both hits
    bool ours_occluded = false, oracle_occluded = false;
};

// Counts of each class and the first mismatches (those of the lowest ray indices, so the examples
// do not depend on the order in which per-thread tallies are merged).
struct Tally {
    static constexpr std::size_t kMaxExamples = 20;

    std::uint64_t agree = 0, ties = 0, grazing = 0, mismatch = 0;
    std::vector<Example> examples;  // mismatches only, sorted by ray index

    void add(Verdict verdict);
    void add(Verdict verdict, std::uint64_t ray_index, const Ray& ray, const Hit& ours, const Hit& oracle);
    void add(Verdict verdict, std::uint64_t ray_index, const Ray& ray, bool ours_occluded, bool oracle_occluded);

    // Classify and add in one step; returns the verdict.
    Verdict record_hit(const Scene& scene, std::uint64_t ray_index, const Ray& ray, const Hit& ours, const Hit& oracle);
    Verdict record_occlusion(const Scene& scene, std::uint64_t ray_index, const Ray& ray, bool ours, bool oracle,
                             std::uint32_t triangle_hint = kNoHit);

    Tally& operator+=(const Tally& other);
    std::uint64_t total() const { return agree + ties + grazing + mismatch; }
    std::uint64_t count(Verdict verdict) const;

private:
    void keep(Example example);
};

// One line: "agree 998 ties 1 grazing 1 mismatch 0 (of 1000)".
std::string summary(const Tally& tally);

}  // namespace beamtrace::oracle
