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

// Scratch of group_by_origin, kept across the cells of a range.
struct CellScratch {
    std::vector<std::uint32_t> label, first, count;
    std::vector<Ray> rays;
    std::vector<std::uint32_t> order;
};

// A cell holding more distinct origins than this is sorted by origin instead.
constexpr std::size_t kMaxLabelledOrigins = 32;

// Rays [begin, end) (and their input indices) in order of their origins' bits, stably.
void sort_by_origin(std::span<Ray> rays, std::span<std::uint32_t> order, std::uint32_t begin, std::uint32_t end,
                    CellScratch& c) {
    c.label.resize(end - begin);
    for (std::uint32_t i = 0; i < end - begin; ++i) c.label[i] = i;
    std::stable_sort(c.label.begin(), c.label.end(), [&](std::uint32_t a, std::uint32_t b) {
        return origin_bits(rays[begin + a]) < origin_bits(rays[begin + b]);
    });
    c.rays.assign(rays.begin() + begin, rays.begin() + end);
    c.order.assign(order.begin() + begin, order.begin() + end);
    for (std::uint32_t i = 0; i < end - begin; ++i) {
        rays[begin + i] = c.rays[c.label[i]];
        order[begin + i] = c.order[c.label[i]];
    }
}

// Rays [begin, end) (and their input indices) put so that each origin's rays are together, stably
// (a ray keeps its place among the rays of its origin); unchanged when they already are. The origins
// follow in the order of their first rays: found by comparing each ray with the distinct origins met
// so far (a cell holds a few hit points, each the origin of all its pixel's rays), then a counting
// sort by origin. Cells of more than kMaxLabelledOrigins origins are sorted by their origins' bits.
void group_by_origin(std::span<Ray> rays, std::span<std::uint32_t> order, std::uint32_t begin, std::uint32_t end,
                     CellScratch& c) {
    const std::uint32_t n = end - begin;
    c.label.resize(n);
    c.first.clear();
    bool grouped = true;  // no origin comes back after another one's rays
    std::uint32_t last = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        const Ray& r = rays[begin + i];
        std::uint32_t o = last;
        if (i == 0 || !same_origin(r, rays[begin + c.first[last]])) {
            o = std::uint32_t(c.first.size());
            for (std::uint32_t d = 0; d < c.first.size(); ++d)
                if (same_origin(r, rays[begin + c.first[d]])) {
                    o = d;
                    break;
                }
            if (o < c.first.size()) {
                grouped = false;
            } else {
                if (c.first.size() == kMaxLabelledOrigins) {
                    sort_by_origin(rays, order, begin, end, c);
                    return;
                }
                c.first.push_back(i);
            }
        }
        c.label[i] = o;
        last = o;
    }
    if (grouped) return;
    c.count.assign(c.first.size() + 1, 0);
    for (std::uint32_t i = 0; i < n; ++i) ++c.count[c.label[i] + 1];
    for (std::size_t d = 1; d < c.count.size(); ++d) c.count[d] += c.count[d - 1];
    c.rays.assign(rays.begin() + begin, rays.begin() + end);
    c.order.assign(order.begin() + begin, order.begin() + end);
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t to = begin + c.count[c.label[i]]++;
        rays[to] = c.rays[i];
        order[to] = c.order[i];
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
    CellScratch scratch;
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
            // One origin cell: each exact origin's rays together, then each origin's run.
            while (e < end && keys[e] == key) ++e;
            if (e - k > 1) group_by_origin(rays, order, k, e, scratch);
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
