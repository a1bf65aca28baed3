#pragma once
// Embree 3 on an AnimatedScene, the two ways its manual offers for moving geometry, as the baselines
// of `beamtrace bench --animation`:
//  - motion_blur: the moving triangles in a geometry with one time step per keyframe
//    (rtcSetGeometryTimeStepCount; Embree spreads the steps uniformly over [0, 1], so the keyframes
//    must be at uniform times over [0, 1]), built once; each ray carries its time. Embree
//    interpolates the vertices itself ((1 - w) p + w q), which may differ from
//    AnimatedScene::position() in the last bit.
//  - dynamic: RTC_SCENE_FLAG_DYNAMIC and RTC_BUILD_QUALITY_LOW (Embree's two-level structure for
//    partial updates); the static triangles in a geometry built once (high quality), the moving ones
//    in another whose vertices set_time() rewrites (AnimatedScene::position(), so a query answers as
//    on at(t)); its build quality is refit (Embree refits that geometry's BVH) or low (rebuilds it).
// Robust (RTC_SCENE_FLAG_ROBUST) like the oracle; zero-area static triangles are left out, as the
// oracle does. Queries go through EmbreeNativeRays (with the rays' times).
#include <cstddef>
#include <cstdint>
#include <memory>

#include "beamtrace/animated_scene.hpp"
#include "oracle/embree_target.hpp"

namespace beamtrace::oracle {

enum class EmbreeMotion { motion_blur, dynamic_refit, dynamic_rebuild };

class EmbreeAnimation : public EmbreeTarget {
public:
    // Builds (and, for the dynamic kinds, places the moving triangles at the scene's start time).
    // Throws beamtrace::Error with Embree's error, or for motion blur on keyframes that are not at
    // uniform times over [0, 1].
    // build_threads: Embree's builder threads (0: Embree's default, every hardware thread).
    EmbreeAnimation(const AnimatedScene& scene, EmbreeMotion motion, int build_threads = 0);
    ~EmbreeAnimation() override;
    EmbreeAnimation(const EmbreeAnimation&) = delete;
    EmbreeAnimation& operator=(const EmbreeAnimation&) = delete;

    // Dynamic kinds: moves the moving triangles to time t and commits (Embree refits or rebuilds
    // them and its top level). Motion blur: nothing to do. Returns the wall seconds taken. Not safe
    // while queries run.
    double set_time(float t);
    double build_seconds() const;  // of the constructor
    std::size_t memory_bytes() const;  // bytes Embree holds now

    RTCSceneTy* native_scene() const override;
    std::uint32_t triangle_id(unsigned geometry, unsigned primitive) const override;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace beamtrace::oracle
