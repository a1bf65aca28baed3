// Groups of the stream tracer (ray_groups.hpp).
#include "stream/ray_groups.hpp"

#include <algorithm>
#include <bit>
#include <tuple>

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

void cut_groups(std::span<Ray> rays, std::span<const std::uint32_t> keys, std::span<std::uint32_t> order,
                int min_group_rays, std::vector<RayGroup>& groups) {
    groups.clear();
    const std::uint32_t n = std::uint32_t(order.size());
    const std::uint32_t min_rays = std::uint32_t(min_group_rays);
    std::vector<std::uint32_t> local;
    std::vector<Ray> cell_rays;
    std::vector<std::uint32_t> cell_order;
    std::uint32_t k = 0;
    while (k < n) {
        const std::uint32_t key = keys[k];
        std::uint32_t e = k + 1;
        RayGroup::Kind kind;
        if (key == kNoSegmentKey) {
            while (e < n && keys[e] == kNoSegmentKey) ++e;
            kind = RayGroup::Kind::no_segment;
        } else if (key & kPencilBit) {
            const std::uint32_t point = key >> kPointShift;
            while (e < n && (keys[e] >> kPointShift) == point) ++e;
            kind = RayGroup::Kind::pencil;
        } else {
            std::uint32_t cell_end = k + 1;
            while (cell_end < n && keys[cell_end] == key) ++cell_end;
            if (cell_end - k > 1) sort_by_origin(rays, order, k, cell_end, local, cell_rays, cell_order);
            const Ray& first = rays[k];
            while (e < n && keys[e] == key && same_origin(rays[e], first)) ++e;
            kind = RayGroup::Kind::origin;
        }
        if (kind != RayGroup::Kind::no_segment && e - k < min_rays) kind = RayGroup::Kind::single;
        add_run(groups, k, e - k, kind);
        k = e;
    }
}

}  // namespace beamtrace::stream
