#pragma once
// CRSH steps 6-7: each top node of the ray hierarchy, depth first, against the objects' spheres (when
// the settings ask), their triangles' spheres, level by level, then the level-1 nodes' rays against
// the triangles that survived, with the watertight test. TBB over top nodes.
#include <cstdint>
#include <span>

#include "beamtrace/query.hpp"
#include "crsh/crsh_impl.hpp"
#include "crsh/ray_hierarchy.hpp"

namespace beamtrace::crsh {

// Closest hits into hits[i] (kOcclusion false) or occlusion into occluded[i] (true) for every ray
// of the hierarchy; the other entries are left alone. With kCount, counts into counters (not null).
template <bool kOcclusion, bool kCount>
void traverse(const Crsh::Impl& impl, bool object_spheres, std::span<const Ray> rays, const RayHierarchy& hierarchy,
              Hit* hits, std::uint8_t* occluded, bool parallel, QueryCounters* counters);

}  // namespace beamtrace::crsh
