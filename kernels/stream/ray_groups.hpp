#pragma once
// The grouping step of the stream tracer: the sorted order cut into what is traced together.
#include <cstdint>
#include <span>
#include <vector>

#include "beamtrace/ray.hpp"

namespace beamtrace::stream {

struct RayGroup {
    enum class Kind : std::uint8_t {
        pencil,      // up to 16 rays through one shared point (a packet for interval traversal)
        origin,      // up to 16 rays with one origin (masked group traversal)
        single,      // rays traced one by one
        no_segment,  // rays that describe no segment: no hit, not occluded
    };
    std::uint32_t begin = 0, count = 0;  // a range of the sorted order
    Kind kind = Kind::single;
};

// Cuts the sorted rays (rays[k] with key keys[k]; order[k] its input index) into groups: runs of one shared point (key bit 31 and the point's bits) and runs of one origin (same
// key, origins equal bit for bit) become groups of at most 16 when they hold at least
// min_group_rays rays; everything else becomes runs of single rays. Rays of one origin key (one
// cell) are first put in order of their origins (stable; rays and order alike), so that rays of one
// origin meet. On `parts` threads of the caller's TBB arena (parts start at changes of key).
void cut_groups(std::span<Ray> rays, std::span<const std::uint32_t> keys, std::span<std::uint32_t> order,
                int min_group_rays, std::vector<RayGroup>& groups, int parts = 1);

}  // namespace beamtrace::stream
