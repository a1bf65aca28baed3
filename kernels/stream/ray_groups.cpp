// Groups of the stream tracer (ray_groups.hpp).
#include "stream/ray_groups.hpp"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "stream/ray_keys.hpp"

namespace beamtrace::stream {

namespace {

// Appends `count` rays from `begin` of one kind: runs of single rays (or of rays without a segment)
// merge with the run before; pencils in equal parts of at most 16 (a run of 17 makes 9 + 8, not 16 +
// 1), cells in equal parts of at most kMaxCellGroup.
void add_run(std::vector<RayGroup>& groups, std::uint32_t begin, std::uint32_t count, RayGroup::Kind kind) {
    if (kind == RayGroup::Kind::single || kind == RayGroup::Kind::no_segment) {
        if (!groups.empty() && groups.back().kind == kind && groups.back().begin + groups.back().count == begin) {
            groups.back().count += count;
            return;
        }
        groups.push_back({begin, count, kind});
        return;
    }
    const std::uint32_t most = kind == RayGroup::Kind::pencil ? 16 : kMaxCellGroup;
    const std::uint32_t parts = (count + most - 1) / most;
    for (std::uint32_t p = 0; p < parts; ++p) {
        // In 64 bits: count * p overflows 32 bits for runs of millions of rays (one light's).
        const std::uint32_t b = begin + std::uint32_t(std::uint64_t(count) * p / parts);
        const std::uint32_t e = begin + std::uint32_t(std::uint64_t(count) * (p + 1) / parts);
        groups.push_back({b, e - b, kind});
    }
}

// cut_groups() over the sorted range [begin, end), which starts and ends at changes of key.
void cut_range(std::span<const std::uint32_t> keys, std::uint32_t begin, std::uint32_t end, std::uint32_t min_rays,
               std::vector<RayGroup>& groups) {
    std::uint32_t k = begin;
    while (k < end) {
        const std::uint32_t key = keys[k];
        std::uint32_t e = k + 1;
        RayGroup::Kind kind = RayGroup::Kind::no_segment;
        if (key == kNoSegmentKey) {
            while (e < end && keys[e] == kNoSegmentKey) ++e;
        } else if (key & kPencilBit) {
            const std::uint32_t point = key >> kPointShift;
            while (e < end && (keys[e] >> kPointShift) == point) ++e;
            kind = RayGroup::Kind::pencil;
        } else {
            while (e < end && keys[e] == key) ++e;
            kind = RayGroup::Kind::cell;
        }
        if (kind != RayGroup::Kind::no_segment && e - k < min_rays) kind = RayGroup::Kind::single;
        add_run(groups, k, e - k, kind);
        k = e;
    }
}

}  // namespace

void cut_groups(std::span<const std::uint32_t> keys, int min_group_rays, std::vector<RayGroup>& groups, int parts) {
    groups.clear();
    const std::uint32_t n = std::uint32_t(keys.size());
    parts = std::max(1, std::min(parts, int(n / 65536) + 1));
    // Parts start at changes of key (an origin cell is never cut; a shared point's run may be).
    std::vector<std::uint32_t> bounds(std::size_t(parts) + 1, n);
    bounds[0] = 0;
    for (int p = 1; p < parts; ++p) {
        std::uint32_t b = std::max(bounds[std::size_t(p - 1)],
                                   std::uint32_t(std::uint64_t(n) * std::uint64_t(p) / std::uint64_t(parts)));
        while (b > 0 && b < n && keys[b] == keys[b - 1]) ++b;
        bounds[std::size_t(p)] = b;
    }
    if (parts == 1) {
        cut_range(keys, 0, n, std::uint32_t(min_group_rays), groups);
        return;
    }
    std::vector<std::vector<RayGroup>> cut(static_cast<std::size_t>(parts));
    tbb::parallel_for(0, parts, [&](int p) {
        cut_range(keys, bounds[std::size_t(p)], bounds[std::size_t(p) + 1], std::uint32_t(min_group_rays),
                  cut[std::size_t(p)]);
    });
    for (const auto& c : cut) groups.insert(groups.end(), c.begin(), c.end());
}

}  // namespace beamtrace::stream
