// Groups of the stream tracer (ray_groups.hpp).
#include "stream/ray_groups.hpp"

#include <algorithm>
#include <bit>
#include <tuple>

#include <tbb/parallel_for.h>

#include "stream/ray_keys.hpp"

namespace beamtrace::stream {

namespace {

bool same_origin(const Ray& a, const Ray& b) {
    return std::bit_cast<std::uint32_t>(a.org.x) == std::bit_cast<std::uint32_t>(b.org.x) &&
           std::bit_cast<std::uint32_t>(a.org.y) == std::bit_cast<std::uint32_t>(b.org.y) &&
           std::bit_cast<std::uint32_t>(a.org.z) == std::bit_cast<std::uint32_t>(b.org.z);
}

std::tuple<std::uint32_t, std::uint32_t, std::uint32_t> origin_bits(const Ray& r) {
    return {std::bit_cast<std::uint32_t>(r.org.x), std::bit_cast<std::uint32_t>(r.org.y),
            std::bit_cast<std::uint32_t>(r.org.z)};
}

// Rays [begin, end) (and their input indices) in order of their origins' bits, stably; unchanged
// when they are already (one origin, or origins met in order).
void sort_by_origin(std::span<Ray> rays, std::span<std::uint32_t> order, std::uint32_t begin, std::uint32_t end,
                    std::vector<std::uint32_t>& local, std::vector<Ray>& cell_rays, std::vector<std::uint32_t>& cell_order) {
    bool sorted = true;
    for (std::uint32_t i = begin + 1; i < end && sorted; ++i) sorted = !(origin_bits(rays[i]) < origin_bits(rays[i - 1]));
    if (sorted) return;
    local.resize(end - begin);
    for (std::uint32_t i = 0; i < end - begin; ++i) local[i] = i;
    std::stable_sort(local.begin(), local.end(), [&](std::uint32_t a, std::uint32_t b) {
        return origin_bits(rays[begin + a]) < origin_bits(rays[begin + b]);
    });
    cell_rays.assign(rays.begin() + begin, rays.begin() + end);
    cell_order.assign(order.begin() + begin, order.begin() + end);
    for (std::uint32_t i = 0; i < end - begin; ++i) {
        rays[begin + i] = cell_rays[local[i]];
        order[begin + i] = cell_order[local[i]];
    }
}

// Appends `count` rays from `begin` of one kind, in groups of at most 16 (kind pencil / origin) or
// as one run of single rays.
void add_run(std::vector<RayGroup>& groups, std::uint32_t begin, std::uint32_t count, RayGroup::Kind kind) {
    if (kind == RayGroup::Kind::single || kind == RayGroup::Kind::no_segment) {
        if (!groups.empty() && groups.back().kind == kind && groups.back().begin + groups.back().count == begin) {
            groups.back().count += count;  // runs of single rays merge
            return;
        }
        groups.push_back({begin, count, kind});
        return;
    }
    // Equal parts of at most 16 (a run of 17 makes 9 + 8, not 16 + 1).
    const std::uint32_t parts = (count + 15) / 16;
    for (std::uint32_t p = 0; p < parts; ++p) {
        // In 64 bits: count * p overflows 32 bits for runs of millions of rays (one light's).
        const std::uint32_t b = begin + std::uint32_t(std::uint64_t(count) * p / parts);
        const std::uint32_t e = begin + std::uint32_t(std::uint64_t(count) * (p + 1) / parts);
        groups.push_back({b, e - b, kind});
    }
}

}  // namespace

namespace {

// cut_groups() over the sorted range [begin, end), which starts and ends at changes of key.
void cut_range(std::span<Ray> rays, std::span<const std::uint32_t> keys, std::span<std::uint32_t> order,
               std::uint32_t begin, std::uint32_t end, std::uint32_t min_rays, std::vector<RayGroup>& groups) {
    std::vector<std::uint32_t> local;
    std::vector<Ray> cell_rays;
    std::vector<std::uint32_t> cell_order;
    const auto add = [&](std::uint32_t k, std::uint32_t e, RayGroup::Kind kind) {
        if (kind != RayGroup::Kind::no_segment && e - k < min_rays) kind = RayGroup::Kind::single;
        add_run(groups, k, e - k, kind);
    };
    std::uint32_t k = begin;
    while (k < end) {
        const std::uint32_t key = keys[k];
        std::uint32_t e = k + 1;
        if (key == kNoSegmentKey) {
            while (e < end && keys[e] == kNoSegmentKey) ++e;
            add(k, e, RayGroup::Kind::no_segment);
        } else if (key & kPencilBit) {
            const std::uint32_t point = key >> kPointShift;
            while (e < end && (keys[e] >> kPointShift) == point) ++e;
            add(k, e, RayGroup::Kind::pencil);
        } else {
            // One origin cell: its rays in order of their exact origins, then each origin's run.
            while (e < end && keys[e] == key) ++e;
            if (e - k > 1) sort_by_origin(rays, order, k, e, local, cell_rays, cell_order);
            for (std::uint32_t r = k; r < e;) {
                std::uint32_t run_end = r + 1;
                while (run_end < e && same_origin(rays[run_end], rays[r])) ++run_end;
                add(r, run_end, RayGroup::Kind::origin);
                r = run_end;
            }
        }
        k = e;
    }
}

}  // namespace

void cut_groups(std::span<Ray> rays, std::span<const std::uint32_t> keys, std::span<std::uint32_t> order,
                int min_group_rays, std::vector<RayGroup>& groups, int parts) {
    groups.clear();
    const std::uint32_t n = std::uint32_t(order.size());
    parts = std::max(1, std::min(parts, int(n / 65536) + 1));
    // Parts start at changes of key (an origin cell is never cut; a shared point's run may be).
    std::vector<std::uint32_t> bounds(std::size_t(parts) + 1, n);
    bounds[0] = 0;
    for (int p = 1; p < parts; ++p) {
        std::uint32_t b = std::max(bounds[std::size_t(p - 1)], std::uint32_t(std::uint64_t(n) * std::uint64_t(p) / std::uint64_t(parts)));
        while (b > 0 && b < n && keys[b] == keys[b - 1]) ++b;
        bounds[std::size_t(p)] = b;
    }
    if (parts == 1) {
        cut_range(rays, keys, order, 0, n, std::uint32_t(min_group_rays), groups);
        return;
    }
    std::vector<std::vector<RayGroup>> cut(static_cast<std::size_t>(parts));
    tbb::parallel_for(0, parts, [&](int p) {
        cut_range(rays, keys, order, bounds[std::size_t(p)], bounds[std::size_t(p) + 1], std::uint32_t(min_group_rays),
                  cut[std::size_t(p)]);
    });
    for (const auto& c : cut) groups.insert(groups.end(), c.begin(), c.end());
}

}  // namespace beamtrace::stream
