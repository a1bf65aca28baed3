#pragma once
// A beamtrace ray as Embree 3 accepts it (the rules are in embree_oracle.hpp): a segment inside
// [0, inf] with every component inside Embree's range, and what it takes to map Embree's t back.
// Shared by the oracle's queries and by the Embree engines' prebuilt ray layouts.
#include <optional>

#include "beamtrace/ray.hpp"

namespace beamtrace::oracle {

struct EmbreeSegment {
    Float3 org, dir;
    float tnear = 0.0f, tfar = 0.0f;
    float shift = 0.0f;    // caller's t = Embree's t / t_scale + shift
    float t_scale = 1.0f;  // a power of two: the direction was divided by it, so Embree's t is multiplied

    // The caller's t of a hit Embree reports at t.
    float caller_t(float t) const { return t / t_scale + shift; }
};

// The segment Embree is given for a ray, or nothing for a ray that describes no segment Embree can
// take (NaN, infinite or out-of-range components, zero direction, tfar < tnear): such rays report no
// hit and are never occluded.
std::optional<EmbreeSegment> to_embree(const Ray& ray);

// Values for packet lanes Embree is told to ignore: a well-formed ray all the same.
inline constexpr EmbreeSegment kIdleLane{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}, 0.0f, 0.0f, 0.0f, 1.0f};

}  // namespace beamtrace::oracle
