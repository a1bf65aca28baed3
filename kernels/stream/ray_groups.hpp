#pragma once
// The grouping step of the stream tracer: the sorted order cut into what is traced together, from
// the sorted keys alone (no ray is read: the trace finds each cell's runs of one origin as it reads
// the cell's rays).
#include <cstdint>
#include <span>
#include <vector>

namespace beamtrace::stream {

struct RayGroup {
    enum class Kind : std::uint8_t {
        pencil,      // up to 16 rays through one shared point (a packet for interval traversal)
        cell,        // rays of one origin cell, each origin's rays next to each other (the sort's
                     // origin hash): traced as groups of one origin where the trace finds enough
                     // rays with one origin, else one by one
        single,      // rays traced one by one
        no_segment,  // rays that describe no segment: no hit, not occluded
    };
    std::uint32_t begin = 0, count = 0;  // a range of the sorted order
    Kind kind = Kind::single;
};

// A cell's rays are cut into groups of at most this many (work for one task at a time).
inline constexpr std::uint32_t kMaxCellGroup = 1024;

// Cuts the sorted order (keys[k] the key of its k-th ray) into groups: runs of one shared point (key
// bit 31 and the point's bits) become pencil groups of at most 16 when they hold at least
// min_group_rays rays; runs of one origin cell (one key) of at least min_group_rays rays become cell
// groups (of at most kMaxCellGroup); everything else becomes runs of single rays. On `parts` threads
// of the caller's TBB arena (parts start at changes of key).
void cut_groups(std::span<const std::uint32_t> keys, int min_group_rays, std::vector<RayGroup>& groups, int parts = 1);

}  // namespace beamtrace::stream
