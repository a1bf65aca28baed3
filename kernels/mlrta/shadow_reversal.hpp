#pragma once
// Shadow rays traced from their light (MLRTA section 6): rays that end at a point light, traced from
// that point, form beams with one origin. Mlrta::occluded applies the policy below to every packet.
#include "beamtrace/ray.hpp"
#include "beamtrace/vec.hpp"

namespace beamtrace::mlrta {

// When every active ray of the packet aims at one point, the light (org + dir, with tnear < 1 and
// tfar <= 1: a shadow ray with direction light - origin), writes each one to `out` as the same
// segment from that point: origin exactly the light (bit for bit, so the packet has one origin),
// direction start - light, parameters [(1 - tfar) / (1 - tnear), 1]. Inactive lanes are copied.
// Returns false and leaves `out` alone when a ray aims elsewhere, or when rounding could move an end
// of a segment by more than `tolerance` (far from the world origin, say). Every check is in float,
// with bounds on the rounding (SSE, four lanes at a time).
bool reverse_towards_light(const Packet16& packet, float tolerance, Packet16& out);

// The tolerance of the policy: 1e-6 of the scene box's diagonal (a tenth of the distance the
// oracle's comparison calls grazing), computed in double (float overflows from about 1e19 on).
double reversal_tolerance(const Box& scene_bounds);

// The policy: a packet whose active rays already share one origin is kept as it is; otherwise
// towards a common light when reverse_towards_light() can; otherwise each active ray
// reversed (reversed(), ray.hpp) when every reversed segment's ends lie within `tolerance` of the
// original's (checked in double); otherwise the packet as it is. Returns whether `out` holds
// reversed rays (out is the packet itself when not). A reversed ray is the same segment, so its
// occlusion is the original's.
bool reverse_for_occlusion(const Packet16& packet, double tolerance, Packet16& out);

}  // namespace beamtrace::mlrta
