#pragma once
// What prebuilt Embree rays (embree_native_rays.hpp) are traced against: a committed Embree scene
// and the map from Embree's (geomID, primID) back to the caller's triangle ids. The oracle is one
// (a static scene); EmbreeAnimation (a moving scene, per-ray times) is the other.
#include <cstdint>

struct RTCSceneTy;  // Embree's scene; declared here so that no Embree header leaks

namespace beamtrace::oracle {

class EmbreeTarget {
public:
    virtual ~EmbreeTarget() = default;
    virtual RTCSceneTy* native_scene() const = 0;
    virtual std::uint32_t triangle_id(unsigned geometry, unsigned primitive) const = 0;
};

}  // namespace beamtrace::oracle
