#pragma once
// The Embree 3 oracle: the same queries as the library's own traversals, answered by Embree in robust
// mode, so that tests and the `beamtrace` command can check our hits against an independent tracer.
//
// Ray semantics (a ray means the points org + t * dir for tnear <= t <= tfar, as in beamtrace/ray.hpp):
//  - Embree only accepts segments inside [0, inf] (this Debian build even asserts tnear >= 0 and
//    aborts otherwise). A ray with a finite negative tnear is therefore handed to Embree with its
//    origin moved to org + tnear * dir (rounded to float) and the segment shifted to [0, tfar - tnear];
//    the reported t is shifted back. The moved origin is the only extra rounding.
//  - Rays that describe no segment report no hit and are never occluded, without calling Embree:
//    tfar < tnear (Embree also misses those: its traversal clips every box and triangle to the empty
//    interval, verified by the tests), a NaN anywhere, an infinite origin or direction component, an
//    infinite tnear, or a zero direction vector. (Such rays could also trip the assertions this
//    Embree build is compiled with, so they are filtered out before Embree sees them.)
//  - Embree asserts (and aborts) when an origin or direction component exceeds 1.844e18 in
//    magnitude. A larger direction is divided by a power of two before Embree sees it (t scaled
//    back exactly); a ray whose origin (after the tnear shift) lies beyond that reports no hit.
//  - A direction with some zero components is fine: Embree's box test uses a safe reciprocal
//    (zero components replaced by a tiny value), so axis-parallel rays work; the tests check them.
//  - Hits exactly at tnear or tfar may be reported or not (Embree makes no promise there).
//  - Degenerate (zero-area) triangles are never handed to Embree, so they can never be hit; Embree
//    would miss them too (its Pluecker test rejects a zero determinant; the tests check that on raw
//    Embree as well). Triangle ids stay the scene's: Embree's primID is mapped back.
//
// Threads: after construction every query is const and may run concurrently from any number of
// threads (TBB workers included). Each call uses its own RTCIntersectContext on the stack, and a
// committed Embree scene is read-only.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"
#include "oracle/embree_target.hpp"


namespace beamtrace::oracle {

struct EmbreeSceneOptions {
    // RTC_SCENE_FLAG_ROBUST: watertight triangle tests, the guarantee our own engines give. Off only
    // to measure what Embree's faster, non-robust mode gains (docs/oracle.md); the oracle of the
    // tests and of every comparison is always robust.
    bool robust = true;
    // Threads Embree's builder may use (its device's "threads" setting); 0: Embree's default, every
    // hardware thread. Benchmarks that count build time set it to the run's --threads.
    int build_threads = 0;
    bool operator==(const EmbreeSceneOptions&) const = default;
};

class EmbreeOracle : public EmbreeTarget {
public:
    // Builds an Embree scene (RTC_SCENE_FLAG_ROBUST unless options say otherwise,
    // RTC_BUILD_QUALITY_HIGH) from a copy of the scene's vertices and indices; nothing is shared with
    // the Scene afterwards. Throws beamtrace::Error with Embree's error text if the device, the scene
    // or the build fails.
    explicit EmbreeOracle(const Scene& scene, const EmbreeSceneOptions& options = {});
    ~EmbreeOracle() override;
    EmbreeOracle(EmbreeOracle&&) noexcept;
    EmbreeOracle& operator=(EmbreeOracle&&) noexcept;
    EmbreeOracle(const EmbreeOracle&) = delete;
    EmbreeOracle& operator=(const EmbreeOracle&) = delete;

    // Closest hit (rtcIntersect1): t is Embree's tfar after the call, triangle the scene's id, u and v
    // Embree's barycentrics. No hit: Hit{} (t = infinity, triangle = kNoHit).
    Hit intersect1(const Ray& ray) const;
    // Any hit (rtcOccluded1).
    bool occluded1(const Ray& ray) const;
    // rtcIntersect16 over the rays whose bit is set in packet.active; every other ray reports Hit{}.
    void intersect16(const Packet16& packet, PacketHits16& hits) const;
    // rtcOccluded16; bit i of the result is set when ray i is active and occluded.
    std::uint32_t occluded16(const Packet16& packet) const;

    // Wall time of building the Embree scene (buffers, geometry and rtcCommitScene).
    double build_seconds() const;
    // Bytes Embree holds for this oracle after the build, as counted by the device's memory monitor
    // callback (buffers, BVH and builder leftovers).
    std::size_t memory_bytes() const;
    // Triangles handed to Embree (the scene's triangles minus the degenerate ones).
    std::size_t embree_triangle_count() const;
    // Whether the scene was built with RTC_SCENE_FLAG_ROBUST.
    bool robust() const;
    // The options the scene was built with.
    const EmbreeSceneOptions& options() const;

    // For callers that issue Embree queries themselves (EmbreeNativeRays: rays prebuilt in
    // Embree's layouts): the committed scene, and the scene's triangle id of an Embree primID.
    RTCSceneTy* native_scene() const override;
    std::uint32_t triangle_id(unsigned embree_prim) const;
    std::uint32_t triangle_id(unsigned geometry, unsigned embree_prim) const override;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace beamtrace::oracle
