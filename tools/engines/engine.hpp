#pragma once
// An engine: one way of answering closest-hit and occlusion queries for a RaySet. The benchmark,
// the renderer and the differential tests drive every engine through this one interface. The
// library's engines are thin adapters of its query contract (beamtrace/query.hpp): the threads, the
// shadow-ray policy and the answers' layout are the library's.
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "beamtrace/crsh.hpp"
#include "beamtrace/kdtree.hpp"
#include "beamtrace/mlrta.hpp"
#include "beamtrace/ray_classification.hpp"
#include "beamtrace/scene.hpp"
#include "beamtrace/sorted_lists.hpp"
#include "beamtrace/space_time_classification.hpp"
#include "beamtrace/stream.hpp"
#include "beamtrace/vlf.hpp"
#include "oracle/embree_oracle.hpp"
#include "rays/ray_set.hpp"

namespace beamtrace::workload {

// Settings engines may use; each engine reads what concerns it.
struct EngineOptions {
    KdBuildRules kd_rules;
    MlrtaSettings mlrta;  // mlrta; kd16 reads mlrta.experimental.triangle_culling
    VlfOptions vlf;       // vlf, vlf-fast: directions, tiles, depth, eager, order (the mode is the engine's)
    StreamSettings stream;  // stream, embree-sorted (its order)
    // embree1, embree16, embree-stream: build Embree's scene with RTC_SCENE_FLAG_ROBUST (the
    // watertight guarantee our engines give); off only to measure what Embree's fast mode gains.
    bool embree_robust = true;
    // Embree engines: threads of Embree's builder (0: Embree's default, every hardware thread).
    // `bench --animation`, which counts build time, sets it to --threads.
    int embree_build_threads = 0;
    // Embree engines: an Embree scene already built on the very Scene given to build() (the caller's
    // promise), e.g. the benchmark's oracle. When its options equal {embree_robust,
    // embree_build_threads} the engines still build (and time, and count) their own, but free it at
    // once and trace this one: the same BVH, without three copies held (the room: 88 MB each).
    std::shared_ptr<const oracle::EmbreeOracle> embree_scene;
    // Embree engines: a ray set of more packets is prebuilt in parts of this many packets inside each
    // timed pass (each part converted untimed, then timed), so that 16.8 million AO rays do not hold
    // three engines' layouts (2.9 GB) at once. Tests set it small.
    std::size_t embree_part_packets = kDefaultEmbreePartPackets;
    static constexpr std::size_t kDefaultEmbreePartPackets = std::size_t{1} << 16;  // 2^20 ray slots
    // Progress of long builds in [0, 1]; may be empty.
    std::function<void(double)> build_progress;
    // crsh: the scene's objects (SceneSource::object_of_triangle; must outlive build()); empty: the
    // whole scene is one object.
    std::span<const std::uint32_t> object_of_triangle;
    // crsh, rah: fanout, levels, key bits, segment bound (sort, object spheres and the key kind are the
    // engines').
    CrshSettings crsh;
    // crsh, rah: the work budget. A ray set whose predicted top-level sphere tests
    // (Crsh::predicted_top_level_tests) exceed it is refused with an error (docs/crsh.md).
    std::uint64_t crsh_budget = kDefaultCrshBudget;
    // raycls: depths, candidates, cache, light buffers, memory budget.
    RayClsSettings raycls;
    // raycls-st: time bins and the moving part's trees (its static part takes `raycls`).
    SpaceTimeSettings space_time;
    static constexpr std::uint64_t kDefaultCrshBudget = 1'000'000'000ull;
    // lists, lists-flat: the hierarchy's rules (flat is the engine's).
    SortedListRules lists;
};

// An engine's answers to a ray set's rays: per slot (packet * 16 + lane) for the comparison, the
// counts and the pictures. Engines that answer by packet, or a compact span of the active rays,
// fill that form instead, which to_slots() spreads (outside any timed region). Inactive slots: no
// hit, not occluded.
struct EngineAnswers {
    enum class Form { slots, packets, rays };
    Form form = Form::slots;                     // which form holds the last answers
    std::vector<Hit> hits;                       // per slot: closest hits
    std::vector<std::uint8_t> occluded;          // per slot: 1 = occluded
    std::vector<PacketHits16> packet_hits;       // per packet, as the library's packet queries give them
    std::vector<std::uint32_t> packet_occluded;  // per packet: bit i = lane i occluded
    std::vector<Hit> ray_hits;                   // per active ray, in slot order
    std::vector<std::uint8_t> ray_occluded;
    const std::vector<std::uint32_t>* ray_slots = nullptr;  // the slot of each active ray (the engine's)

    // Makes the per-slot form current (a no-op when it already is).
    void to_slots(const RaySet& rays, bool closest);
};

// The answers of an accelerator's packet queries (the library's query contract, query.hpp) to the
// ray set's packets, by packet: what kd16, vlf and, for rays that form no image, mlrta do.
template <class Accelerator>
void answer_packets(const Accelerator& accelerator, const RaySet& rays, bool closest, EngineAnswers& answers,
                    const QueryOptions& options) {
    answers.form = EngineAnswers::Form::packets;
    const std::span<const Packet16> packets(rays.packets);
    if (closest) {
        answers.packet_hits.resize(packets.size());
        accelerator.intersect(packets, std::span<PacketHits16>(answers.packet_hits), options);
    } else {
        answers.packet_occluded.resize(packets.size());
        accelerator.occluded(packets, std::span<std::uint32_t>(answers.packet_occluded), options);
    }
}

class Engine {
public:
    virtual ~Engine() = default;
    virtual std::string name() const = 0;
    // Builds the engine's structures for the scene (timed by the engine itself).
    virtual void build(const Scene& scene, const EngineOptions& options) = 0;
    virtual double build_seconds() const = 0;
    virtual std::size_t memory_bytes() const = 0;

    // Answers every ray of the set (closest hits when `closest`, else occlusion) into `answers`, in
    // the engine's own form (per packet or per slot; see EngineAnswers).
    virtual void trace(const RaySet& rays, bool closest, EngineAnswers& answers, int threads) const = 0;
    // The same, per slot: hits / occluded are resized to rays.slots().
    void intersect(const RaySet& rays, std::vector<Hit>& hits, int threads) const;
    void occluded(const RaySet& rays, std::vector<std::uint8_t>& occluded, int threads) const;

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
    // none); returns the seconds of the timed region and leaves the answers, per slot, in `answers`.
    // The timed region is the engine's query and nothing else (default: trace() for primary rays'
    // closest hits, else occlusion); the answers are spread into slots after it.
    virtual double timed_pass(const RaySet& rays, EngineAnswers& answers, int threads, int variant);

    // Engine statistics (build and traversal counters). Engines that count do so in an extra,
    // untimed pass over the same rays with the counting variant of the same traversal code.
    virtual nlohmann::json stats(const RaySet& rays) const = 0;
    // Engines that trace tiles of beams report each tile's entry point and subtree size (MLRTA's
    // geometric complexity); the others return false.
    virtual bool tile_complexity(const RaySet&, std::vector<TileInfo>&) const { return false; }
};

// Every engine name, in the order of the table: embree1, embree16, embree-stream, brute, kd1, ...
const std::vector<std::string>& engine_names();
// Throws beamtrace::Error naming the known engines for an unknown name.
std::unique_ptr<Engine> make_engine(const std::string& name);

}  // namespace beamtrace::workload
