#pragma once
// An engine: one way of answering closest-hit and occlusion queries for a RaySet. The benchmark,
// the renderer and the differential tests drive every engine through this one interface.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "beamtrace/kdtree.hpp"
#include "beamtrace/mlrta.hpp"
#include "beamtrace/scene.hpp"
#include "beamtrace/vlf.hpp"
#include "workload/ray_set.hpp"

namespace beamtrace::workload {

// Settings engines may use; each engine reads what concerns it.
struct EngineOptions {
    KdBuildRules kd_rules;
    MlrtaSettings mlrta;
    VlfOptions vlf;  // vlf, vlf-fast: directions, tiles, depth, eager
    // vlf, vlf-fast: trace rays in the given packets ("input"), binned by PSF ("psf"), or binned
    // for occlusion rays only ("auto": secondary rays are incoherent, primary packets are not).
    std::string vlf_order = "auto";
    // embree1, embree16, embree-stream: build Embree's scene with RTC_SCENE_FLAG_ROBUST (the
    // watertight guarantee our engines give); off only to measure what Embree's fast mode gains.
    bool embree_robust = true;
    // Progress of long builds in [0, 1]; may be empty.
    std::function<void(double)> build_progress;
};

// An engine's answers to a ray set's rays, per slot: hits (primary mode) or occlusion (1 =
// occluded; shadow and ao modes). Inactive slots: no hit, not occluded.
struct EngineAnswers {
    std::vector<Hit> hits;
    std::vector<std::uint8_t> occluded;
};

class Engine {
public:
    virtual ~Engine() = default;
    virtual std::string name() const = 0;
    // Builds the engine's structures for the scene (timed by the engine itself).
    virtual void build(const Scene& scene, const EngineOptions& options) = 0;
    virtual double build_seconds() const = 0;
    virtual std::size_t memory_bytes() const = 0;
    // hits / occluded are resized to rays.slots(); inactive slots report no hit / not occluded.
    virtual void intersect(const RaySet& rays, std::vector<Hit>& hits, int threads) const = 0;
    virtual void occluded(const RaySet& rays, std::vector<std::uint8_t>& occluded, int threads) const = 0;

    // ---- Timed passes (beamtrace bench and trade) ----
    // Untimed work before the timed passes over these rays (engines that trace rays in a layout of
    // their own build it here). Called after build(); timed_pass() calls it itself when needed.
    virtual void prepare(const RaySet&) {}
    // The ways an engine can trace the same rays, each timed on every pass (Embree: its two context
    // flags); the fastest is the engine's speed. Empty: one way. timing_variant_key() names the
    // statistic that reports which one was fastest ("context_flag").
    virtual std::vector<std::string> timing_variants() const { return {}; }
    virtual std::string timing_variant_key() const { return "variant"; }
    // One pass over every ray in the given variant (an index into timing_variants(), 0 when there are
    // none); returns the seconds of the timed region and leaves the answers in `answers`. The timed
    // region is what the engine needs to answer the rays as given (default: intersect() for primary
    // rays, occluded() otherwise); an engine that traces its own layout converts the rays and the
    // answers outside it.
    virtual double timed_pass(const RaySet& rays, EngineAnswers& answers, int threads, int variant);

    // Engine statistics (build and traversal counters). Engines that count do so in an extra,
    // untimed pass over the same rays with the counting variant of the same traversal code.
    virtual nlohmann::json stats(const RaySet& rays) const = 0;
    // Engines that trace tiles of beams report each tile's entry point and subtree size (MLRTA's
    // geometric complexity); the others return false.
    virtual bool tile_complexity(const RaySet&, std::vector<TileInfo>&) const { return false; }
};

// Every engine name, in the order of the table: embree1, embree16, brute, kd1, kd16, mlrta, ...
const std::vector<std::string>& engine_names();
// Throws beamtrace::Error naming the known engines for an unknown name.
std::unique_ptr<Engine> make_engine(const std::string& name);

}  // namespace beamtrace::workload
