// Classification of disagreements between our hits and the oracle's.
#include "oracle/comparison.hpp"

#include <algorithm>
#include <cmath>

#include "oracle/ray_geometry.hpp"

namespace beamtrace::oracle {

namespace {

// A triangle id some query may legitimately report.
bool hittable(const Scene& scene, std::uint32_t id) { return id < scene.triangle_count() && !scene.is_degenerate(id); }

bool same_t(float a, float b) {
    const double ta = a, tb = b;
    const double tolerance = 1e-4 * std::max({1.0, std::fabs(ta), std::fabs(tb)});
    return std::fabs(ta - tb) <= tolerance;  // false for NaN
}

// A disagreement the ends of the segment explain: the ray's line crosses some triangle within reach
// of tnear or tfar, where float t decides whether the crossing is in or out (tracers round it
// differently: the room's AO rays that end on the floor, docs/oracle.md), and crosses none on the
// segment farther than that from both ends (there the answer would not be in doubt).
bool ends_explain(const Scene& scene, const Ray& ray, double reach) {
    const EndCrossings c = end_crossings(scene, ray, reach);
    return c.near_end && !c.inside;
}

}  // namespace

const char* to_string(Verdict verdict) {
    switch (verdict) {
        case Verdict::agree:
            return "agree";
        case Verdict::ties:
            return "ties";
        case Verdict::grazing:
            return "grazing";
        case Verdict::mismatch:
            return "mismatch";
    }
    return "unknown";
}

Verdict classify_hit(const Scene& scene, const Ray& ray, const Hit& ours, const Hit& oracle) {
    if (ours.hit() && !hittable(scene, ours.triangle)) return Verdict::mismatch;
    if (oracle.hit() && !hittable(scene, oracle.triangle)) return Verdict::mismatch;
    if (!ours.hit() && !oracle.hit()) return Verdict::agree;
    if (ours.hit() && oracle.hit() && same_t(ours.t, oracle.t))
        return ours.triangle == oracle.triangle ? Verdict::agree : Verdict::ties;

    const RaySegment segment = clip_to_scene(scene, ray);
    const double reach = grazing_distance(scene);
    for (const Hit* h : {&ours, &oracle}) {
        if (h->hit() && edge_distance(scene.triangle(h->triangle), segment) <= reach) return Verdict::grazing;
    }
    // One side hit a triangle where the ray's line crosses it within reach of an end of the segment,
    // the other nothing, and nothing is crossed on the segment away from its ends: the two tracers'
    // float t fall on the two sides of tnear or tfar.
    if (ours.hit() != oracle.hit()) {
        const Hit& only = ours.hit() ? ours : oracle;
        if (end_distance(scene.triangle(only.triangle), ray) <= reach && ends_explain(scene, ray, reach))
            return Verdict::grazing;
    }
    return Verdict::mismatch;
}

Verdict classify_occlusion(const Scene& scene, const Ray& ray, bool ours, bool oracle, std::uint32_t triangle_hint) {
    if (ours == oracle) return Verdict::agree;
    const RaySegment segment = clip_to_scene(scene, ray);
    const double reach = grazing_distance(scene);
    if (triangle_hint != kNoHit) {
        if (!hittable(scene, triangle_hint)) return Verdict::mismatch;
        const Triangle& t = scene.triangle(triangle_hint);
        if (edge_distance(t, segment) <= reach) return Verdict::grazing;
        return end_distance(t, ray) <= reach && ends_explain(scene, ray, reach) ? Verdict::grazing : Verdict::mismatch;
    }
    // No hint: the "occluded" side hit some triangle the ray reaches. The triangles that can make
    // this a grazing case are those with an edge within reach of the ray, whether the exact
    // (double-precision) ray passes just inside them or just outside, so search for exactly those;
    // then the segment's ends (above).
    if (near_edge_of_any(scene, segment, reach)) return Verdict::grazing;
    return ends_explain(scene, ray, reach) ? Verdict::grazing : Verdict::mismatch;
}

void Tally::add(Verdict verdict) {
    switch (verdict) {
        case Verdict::agree:
            ++agree;
            break;
        case Verdict::ties:
            ++ties;
            break;
        case Verdict::grazing:
            ++grazing;
            break;
        case Verdict::mismatch:
            ++mismatch;
            break;
    }
}

void Tally::add(Verdict verdict, std::uint64_t ray_index, const Ray& ray, const Hit& ours, const Hit& oracle) {
    add(verdict);
    if (verdict != Verdict::mismatch) return;
    Example e;
    e.ray_index = ray_index;
    e.ray = ray;
    e.ours = ours;
    e.oracle = oracle;
    keep(e);
}

void Tally::add(Verdict verdict, std::uint64_t ray_index, const Ray& ray, bool ours_occluded, bool oracle_occluded) {
    add(verdict);
    if (verdict != Verdict::mismatch) return;
    Example e;
    e.ray_index = ray_index;
    e.ray = ray;
    e.occlusion = true;
    e.ours_occluded = ours_occluded;
    e.oracle_occluded = oracle_occluded;
    keep(e);
}

Verdict Tally::record_hit(const Scene& scene, std::uint64_t ray_index, const Ray& ray, const Hit& ours,
                          const Hit& oracle) {
    const Verdict v = classify_hit(scene, ray, ours, oracle);
    add(v, ray_index, ray, ours, oracle);
    return v;
}

Verdict Tally::record_occlusion(const Scene& scene, std::uint64_t ray_index, const Ray& ray, bool ours, bool oracle,
                                std::uint32_t triangle_hint) {
    const Verdict v = classify_occlusion(scene, ray, ours, oracle, triangle_hint);
    add(v, ray_index, ray, ours, oracle);
    return v;
}

void Tally::keep(Example example) {
    if (examples.size() >= kMaxExamples && example.ray_index >= examples.back().ray_index) return;
    const auto at = std::upper_bound(examples.begin(), examples.end(), example.ray_index,
                                     [](std::uint64_t i, const Example& e) { return i < e.ray_index; });
    examples.insert(at, example);
    if (examples.size() > kMaxExamples) examples.pop_back();
}

Tally& Tally::operator+=(const Tally& other) {
    agree += other.agree;
    ties += other.ties;
    grazing += other.grazing;
    mismatch += other.mismatch;
    for (const Example& e : other.examples) keep(e);
    return *this;
}

std::uint64_t Tally::count(Verdict verdict) const {
    switch (verdict) {
        case Verdict::agree:
            return agree;
        case Verdict::ties:
            return ties;
        case Verdict::grazing:
            return grazing;
        case Verdict::mismatch:
            return mismatch;
    }
    return 0;
}

std::string summary(const Tally& t) {
    return "agree " + std::to_string(t.agree) + " ties " + std::to_string(t.ties) + " grazing " +
           std::to_string(t.grazing) + " mismatch " + std::to_string(t.mismatch) + " (of " + std::to_string(t.total()) +
           ")";
}

}  // namespace beamtrace::oracle
