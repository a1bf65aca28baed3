#pragma once
// An animated engine: one way of answering the queries of an animation, frame after frame, as
// `beamtrace bench --animation` times them. Each frame brings primary rays (closest hit) and the
// shadow rays made from their hits (occlusion); every ray carries a time, and the answer it must give
// is the one a static engine built on AnimatedScene::at(time) gives. Engines keep what they like
// between frames (that is the point of raycls-st); the frames come in order.
//
// Engines: raycls-st (SpaceTimeClassification: the static part classified once, the moving triangles
// per time bin), raycls-st-packets (the same, its static part traced by the kd-tree's 4x4 packets), embree-mb (Embree's motion blur), embree-refit and embree-dynamic (Embree's dynamic
// scene, moving triangles refitted or rebuilt per time), and every static engine of engine.hpp by its
// own name, rebuilt on at(t) for each distinct time of a frame (what a renderer without motion support
// does).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "beamtrace/animated_scene.hpp"
#include "engines/engine.hpp"
#include "oracle/embree_animation.hpp"
#include "rays/ray_set.hpp"

namespace beamtrace::workload {

// One frame's rays. Both sets have the same slots (shadow slot k starts at primary slot k's hit).
struct FrameRays {
    RaySet primary;                // closest hit
    RaySet shadow;                 // occlusion
    std::vector<float> slot_time;  // per slot: the time of its rays
    std::vector<float> times;      // the distinct times of the frame, increasing
};

// Per slot (inactive slots: no hit, not occluded).
struct FrameAnswers {
    std::vector<Hit> primary;
    std::vector<std::uint8_t> shadow;
};

// Seconds of one frame: build (per-frame rebuilds, refits, snapshots) and trace (the queries, with
// whatever lazy work they do).
struct FrameSeconds {
    double build = 0.0, trace = 0.0;
};

class AnimatedEngine {
public:
    virtual ~AnimatedEngine() = default;
    virtual std::string name() const = 0;
    // Builds what every frame shares (timed by the engine; the seconds are part of its total).
    virtual double start(const AnimatedScene& scene, const EngineOptions& options) = 0;
    // Answers one frame, per slot, into `answers`.
    virtual FrameSeconds trace_frame(const FrameRays& frame, FrameAnswers& answers, int threads) = 0;
    // Bytes the engine holds now (its structures; not the rays).
    virtual std::size_t memory_bytes() const = 0;
    // Whether the engine rebuilds its whole structure for every time of a frame (the static engines;
    // the baselines "rebuilt per frame"). raycls-st and the Embree motion engines keep what does not
    // move.
    virtual bool rebuilds_per_frame() const = 0;
    virtual nlohmann::json stats() const { return nlohmann::json::object(); }
};

// raycls-st, raycls-st-packets, embree-mb, embree-refit, embree-dynamic, then every static engine name.
const std::vector<std::string>& animated_engine_names();
// Throws beamtrace::Error naming the known engines for an unknown name.
std::unique_ptr<AnimatedEngine> make_animated_engine(const std::string& name);

// The rays of `rays` whose slot time is t (the other lanes made inactive): what a per-time rebuild
// traces. Keeps the packets (and so the image layout).
RaySet rays_at_time(const RaySet& rays, const std::vector<float>& slot_time, float t);

// Constructors (one per file).
// raycls-st, or raycls-st-packets (static part by the kd-tree's packet traversal).
std::unique_ptr<AnimatedEngine> make_space_time_engine(bool packets);
std::unique_ptr<AnimatedEngine> make_embree_motion_engine(oracle::EmbreeMotion motion);
std::unique_ptr<AnimatedEngine> make_rebuild_engine(const std::string& static_engine);

}  // namespace beamtrace::workload
