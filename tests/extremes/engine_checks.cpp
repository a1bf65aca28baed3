#include "extremes/engine_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "extremes/exact_reference.hpp"
#include "oracle/ray_geometry.hpp"
#include "support/differential.hpp"
#include "experiments/bench_run.hpp"

namespace beamtrace::test {

using workload::Mode;
using workload::RaySet;

std::vector<EngineUnderTest> build_engines(const Scene& scene, const EngineChoice& choice) {
    std::vector<std::string> names = {"kd1", "kd16", "mlrta", "vlf", "stream", "raycls"};
    if (choice.brute) names.push_back("brute");
    if (choice.vlf_fast) names.push_back("vlf-fast");
    if (choice.crsh) names.insert(names.end(), {"crsh", "rah"});
    if (choice.lists) names.push_back("lists");
    if (choice.lists && choice.brute) names.push_back("lists-flat");  // O(triangles) per ray, as brute
    std::vector<EngineUnderTest> engines;
    for (const std::string& name : names) {
        EngineUnderTest e;
        e.name = name;
        e.exact = name != "vlf-fast";
        e.engine = workload::make_engine(name);
        e.engine->build(scene, choice.options);
        engines.push_back(std::move(e));
    }
    return engines;
}

namespace {

Packet16 idle_packet() {
    Packet16 p;
    p.active = 0;
    const Ray idle{{0, 0, 0}, 0.0f, {0, 0, 1}, 0.0f};
    for (int i = 0; i < 16; ++i) p.set_ray(i, idle);
    return p;
}

// The grazing distance as a parameter range of this ray.
double end_window(const Scene& scene, const Ray& ray) {
    return oracle::grazing_distance(scene) / std::sqrt(double(dot(ray.dir, ray.dir)));
}

// Exact geometry's closest hit on [lo, hi] of the ray's line (float limits rounded outwards).
Hit exact_on(const Scene& scene, Ray ray, double lo, double hi) {
    ray.tnear = std::nextafter(float(lo), -kInfinity);
    ray.tfar = std::nextafter(float(hi), kInfinity);
    return exact_intersect(scene, ray);
}

// A surface within the window of tnear (start) or of tfar (end), by exact geometry.
bool surface_at_start(const Scene& scene, const Ray& ray, double w) {
    return exact_on(scene, ray, ray.tnear - w, ray.tnear + w).hit();
}
bool surface_at_end(const Scene& scene, const Ray& ray, double w) {
    return std::isfinite(ray.tfar) && exact_on(scene, ray, ray.tfar - w, ray.tfar + w).hit();
}

bool hit_ends_explain(const Scene& scene, const Ray& ray, const Hit& a, const Hit& b) {
    if (!well_formed(ray)) return false;
    const double w = end_window(scene, ray);
    // One side found a surface at the start the other did not: the other must be right about the rest.
    const Hit& nearer = (a.hit() && (!b.hit() || a.t < b.t)) ? a : b;
    const Hit& farther = &nearer == &a ? b : a;
    if (nearer.hit() && nearer.t <= ray.tnear + w && surface_at_start(scene, ray, w)) {
        Ray rest = ray;
        rest.tnear = std::nextafter(float(ray.tnear + w), kInfinity);
        if (rest.tnear > rest.tfar) return !farther.hit() || farther.t <= ray.tnear + w;
        return oracle::classify_hit(scene, rest, farther, exact_intersect(scene, rest)) != oracle::Verdict::mismatch;
    }
    // One side hit a surface at the end, the other nothing.
    const Hit& only = a.hit() ? a : b;
    return a.hit() != b.hit() && only.t >= ray.tfar - w && surface_at_end(scene, ray, w);
}

bool occlusion_ends_explain(const Scene& scene, const Ray& ray) {
    if (!well_formed(ray)) return false;
    const double w = end_window(scene, ray);
    if (!surface_at_start(scene, ray, w) && !surface_at_end(scene, ray, w)) return false;
    Ray inner = ray;
    inner.tnear = std::nextafter(float(ray.tnear + w), kInfinity);
    inner.tfar = std::nextafter(float(ray.tfar - w), -kInfinity);
    return inner.tnear > inner.tfar || !exact_occluded(scene, inner);
}

}  // namespace

void Comparison::record_hit(const Scene& scene, std::uint64_t index, const Ray& ray, const Hit& ours,
                            const Hit& reference) {
    const oracle::Verdict v = oracle::classify_hit(scene, ray, ours, reference);
    if (v == oracle::Verdict::mismatch && hit_ends_explain(scene, ray, ours, reference))
        ++at_end;
    else
        tally.add(v, index, ray, ours, reference);
}

void Comparison::record_occlusion(const Scene& scene, std::uint64_t index, const Ray& ray, bool ours, bool reference) {
    const oracle::Verdict v = oracle::classify_occlusion(scene, ray, ours, reference);
    if (v == oracle::Verdict::mismatch && occlusion_ends_explain(scene, ray))
        ++at_end;
    else
        tally.add(v, index, ray, ours, reference);
}

std::string Comparison::summary() const {
    std::string s = oracle::summary(tally);
    if (at_end > 0) s += " + " + std::to_string(at_end) + " at a segment end";
    return s;
}

RaySet ray_set(const std::vector<Ray>& rays, Mode mode) {
    RaySet set;
    set.mode = mode;
    set.width = int(rays.size());
    set.height = 1;
    set.packets.assign((rays.size() + 15) / 16, idle_packet());
    set.pixel.assign(set.packets.size() * 16, workload::kNoPixel);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        Packet16& p = set.packets[i / 16];
        p.set_ray(int(i % 16), rays[i]);
        p.active |= 1u << (i % 16);
        set.pixel[i] = std::uint32_t(i);
    }
    set.ray_count = rays.size();
    return set;
}

RaySet image_ray_set(const std::vector<Ray>& rays, int width, Mode mode) {
    RaySet set;
    set.mode = mode;
    set.width = width;
    set.height = int((rays.size() + std::size_t(width) - 1) / std::size_t(width));
    set.packets_x = (width + 3) / 4;
    set.packets_y = (set.height + 3) / 4;
    set.packets.assign(std::size_t(set.packets_x) * std::size_t(set.packets_y), idle_packet());
    set.pixel.assign(set.packets.size() * 16, workload::kNoPixel);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const int x = int(i % std::size_t(width)), y = int(i / std::size_t(width));
        const std::size_t p = std::size_t(y / 4) * std::size_t(set.packets_x) + std::size_t(x / 4);
        const int lane = (y % 4) * 4 + x % 4;
        set.packets[p].set_ray(lane, rays[i]);
        set.packets[p].active |= 1u << lane;
        set.pixel[p * 16 + std::size_t(lane)] = std::uint32_t(i);
    }
    set.ray_count = rays.size();
    return set;
}

std::vector<Ray> rays_of(const RaySet& set) {
    std::vector<Ray> rays;
    for (std::size_t slot = 0; slot < set.slots(); ++slot)
        if (set.active(slot)) rays.push_back(set.ray(slot));
    return rays;
}

workload::Workload workload_for(const scenes::SceneSource& source, RaySet rays) {
    workload::WorkloadConfig config;
    config.width = config.height = 4;
    workload::Workload w = workload::make_workload(source, config);
    workload::replace_rays(w, std::move(rays));
    return w;
}

CaseReport check_engines(const std::vector<EngineUnderTest>& engines, const workload::Workload& w,
                         const std::string& what, bool geometry) {
    const Scene& scene = w.source.scene;
    const RaySet& rays = w.rays;
    const bool closest = closest_hit(rays.mode);
    CaseReport report;
    report.what = what;
    std::vector<Hit> exact_hits;
    std::vector<std::uint8_t> exact_occlusion;
    if (geometry) {
        exact_hits.resize(rays.slots());
        exact_occlusion.resize(rays.slots(), 0);
        for (std::size_t slot = 0; slot < rays.slots(); ++slot) {
            if (!rays.active(slot)) continue;
            const Ray r = rays.ray(slot);
            if (closest) {
                exact_hits[slot] = exact_intersect(scene, r);
                report.embree_vs_geometry.record_hit(scene, slot, r, w.reference_hits[slot], exact_hits[slot]);
            } else {
                exact_occlusion[slot] = exact_occluded(scene, r);
                report.embree_vs_geometry.record_occlusion(scene, slot, r, w.reference_occluded[slot] != 0,
                                                           exact_occlusion[slot] != 0);
            }
        }
    }
    for (const EngineUnderTest& e : engines) {
        EngineReport er;
        er.engine = e.name;
        er.exact = e.exact;
        if (closest) {
            std::vector<Hit> hits;
            e.engine->intersect(rays, hits, 1);
            for (std::size_t slot = 0; slot < rays.slots(); ++slot) {
                if (!rays.active(slot)) continue;
                const Ray r = rays.ray(slot);
                er.oracle.record_hit(scene, slot, r, hits[slot], w.reference_hits[slot]);
                if (geometry) er.geometry.record_hit(scene, slot, r, hits[slot], exact_hits[slot]);
            }
        } else {
            std::vector<std::uint8_t> occluded;
            e.engine->occluded(rays, occluded, 1);
            for (std::size_t slot = 0; slot < rays.slots(); ++slot) {
                if (!rays.active(slot)) continue;
                const Ray r = rays.ray(slot);
                er.oracle.record_occlusion(scene, slot, r, occluded[slot] != 0, w.reference_occluded[slot] != 0);
                if (geometry)
                    er.geometry.record_occlusion(scene, slot, r, occluded[slot] != 0, exact_occlusion[slot] != 0);
            }
        }
        report.engines.push_back(std::move(er));
    }
    return report;
}

void print(const CaseReport& r) {
    if (r.embree_vs_geometry.total() > 0)
        std::printf("[%s] embree vs geometry: %s\n", r.what.c_str(), r.embree_vs_geometry.summary().c_str());
    for (const EngineReport& e : r.engines) {
        std::printf("[%s] %-8s vs embree: %s", r.what.c_str(), e.engine.c_str(), e.oracle.summary().c_str());
        if (e.geometry.total() > 0) std::printf(" | vs geometry: %s", e.geometry.summary().c_str());
        std::printf("\n");
    }
    std::fflush(stdout);
}

void expect_exact_engines_clean(const CaseReport& r) {
    print(r);
    const bool geometry = r.embree_vs_geometry.total() > 0;
    const bool embree_consistent = !geometry || r.embree_vs_geometry.tally.mismatch == 0;
    for (const EngineReport& e : r.engines) {
        if (!e.exact) continue;
        if (geometry) expect_no_mismatch(e.geometry.tally, r.what + " " + e.engine + " vs geometry");
        if (embree_consistent) expect_no_mismatch(e.oracle.tally, r.what + " " + e.engine + " vs embree");
    }
}

}  // namespace beamtrace::test
