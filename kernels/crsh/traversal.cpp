#include "crsh/traversal.hpp"

#include <algorithm>
#include <array>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "common/ray_batches.hpp"

namespace beamtrace::crsh {

namespace {

using Counts = QueryCounters::Crsh;

// The candidate lists of one thread, one per level (indices into Impl's triangle arrays).
struct Scratch {
    std::array<std::vector<std::uint32_t>, Counts::kMaxLevels> lists;
};

template <bool kOcclusion, bool kCount>
class Walker {
public:
    Walker(const Crsh::Impl& impl, std::span<const Ray> rays, const RayHierarchy& h, Hit* hits, std::uint8_t* occluded,
           Scratch& scratch, QueryCounters* counters)
        : impl_(impl), rays_(rays), h_(h), hits_(hits), occluded_(occluded), scratch_(scratch), counters_(counters) {}

    void top(std::size_t j, bool object_spheres) {
        const int level = static_cast<int>(h_.levels.size());
        const RayNode& node = h_.levels.back()[j];
        std::vector<std::uint32_t>& list = scratch_.lists[level - 1];
        list.clear();
        if (object_spheres) {
            const std::size_t objects = impl_.object_count();
            if constexpr (kCount) counters_->crsh.object_sphere_tests += objects;
            for (std::size_t o = 0; o < objects; ++o) {
                const Sphere& s = impl_.object_spheres[o];
                if (!sphere_meets_node(node, s.centre.x, s.centre.y, s.centre.z, s.radius)) continue;
                if constexpr (kCount) ++counters_->crsh.object_sphere_hits;
                keep_range(node, impl_.object_first[o], impl_.object_first[o + 1], list, level);
            }
        } else {
            keep_range(node, 0, static_cast<std::uint32_t>(impl_.triangles.size()), list, level);
        }
        if (!list.empty()) descend(node, list, level);
    }

private:
    bool meets(const RayNode& node, std::uint32_t k) const {
        return sphere_meets_node(node, impl_.sphere_x[k], impl_.sphere_y[k], impl_.sphere_z[k], impl_.sphere_r[k]);
    }

    void count_level(int level, std::size_t tested, std::size_t kept) {
        if constexpr (kCount) {
            counters_->crsh.sphere_cone_tests += tested;
            counters_->crsh.level_tests[level - 1] += tested;
            counters_->crsh.level_hits[level - 1] += kept;
        }
    }

    void keep_range(const RayNode& node, std::uint32_t b, std::uint32_t e, std::vector<std::uint32_t>& out, int level) {
        const std::size_t before = out.size();
        for (std::uint32_t k = b; k < e; ++k)
            if (meets(node, k)) out.push_back(k);
        count_level(level, e - b, out.size() - before);
    }

    void keep_list(const RayNode& node, const std::vector<std::uint32_t>& in, std::vector<std::uint32_t>& out,
                   int level) {
        out.clear();
        for (std::uint32_t k : in)
            if (meets(node, k)) out.push_back(k);
        count_level(level, in.size(), out.size());
    }

    // The node (at `level`) kept `list`: its children filter it in turn, or its rays test it.
    void descend(const RayNode& node, const std::vector<std::uint32_t>& list, int level) {
        if (level == 1) {
            final_tests(node, list);
            return;
        }
        const std::vector<RayNode>& below = h_.levels[static_cast<std::size_t>(level - 2)];
        std::vector<std::uint32_t>& kept = scratch_.lists[level - 2];
        for (std::uint32_t c = node.first; c < node.first + node.count; ++c) {
            keep_list(below[c], list, kept, level - 1);
            if (!kept.empty()) descend(below[c], kept, level - 1);
        }
    }

    // Every ray of a level-1 node against the triangles it kept, 8 at a time.
    void final_tests(const RayNode& node, const std::vector<std::uint32_t>& list) {
        const TriangleKernels& kernels = *impl_.kernels;
        const std::size_t n = list.size();
        for (std::uint32_t p = node.first; p < node.first + node.count; ++p) {
            const std::uint32_t i = h_.order[p];
            WatertightRay w = make_watertight_ray(rays_[i]);
            Hit best;
            test_ray_in_batches(
                kernels, w, std::uint32_t(n), [&](std::uint32_t j) { return &impl_.triangles[list[j]]; },
                [&](std::uint32_t j, int m, const LaneHits& lanes) {
                    if constexpr (kCount) {
                        counters_->crsh.triangle_tests += static_cast<std::uint64_t>(m);
                        counters_->triangle_tests += static_cast<std::uint64_t>(m);
                    }
                    if constexpr (kOcclusion) {
                        if (lanes.mask) {
                            occluded_[i] = 1;
                            return false;
                        }
                    } else {
                        // The smallest t; at equal t the smaller triangle id (as brute force, which tests by id).
                        for (std::uint32_t mask = lanes.mask; mask; mask &= mask - 1) {
                            const int b = __builtin_ctz(mask);
                            const std::uint32_t id = impl_.ids[list[j + std::uint32_t(b)]];
                            if (lanes.t[b] < best.t || (lanes.t[b] == best.t && id < best.triangle)) {
                                best = Hit{lanes.t[b], id, lanes.u[b], lanes.v[b]};
                                w.tfar = lanes.t[b];
                            }
                        }
                    }
                    return true;
                });
            if constexpr (!kOcclusion) hits_[i] = best;
        }
    }

    const Crsh::Impl& impl_;
    std::span<const Ray> rays_;
    const RayHierarchy& h_;
    Hit* hits_;
    std::uint8_t* occluded_;
    Scratch& scratch_;
    QueryCounters* counters_;
};

}  // namespace

template <bool kOcclusion, bool kCount>
void traverse(const Crsh::Impl& impl, bool object_spheres, std::span<const Ray> rays, const RayHierarchy& h, Hit* hits,
              std::uint8_t* occluded, bool parallel, QueryCounters* counters) {
    const std::size_t tops = h.top_count();
    if (!parallel || tops < 2) {
        Scratch scratch;
        Walker<kOcclusion, kCount> walker(impl, rays, h, hits, occluded, scratch, counters);
        for (std::size_t j = 0; j < tops; ++j) walker.top(j, object_spheres);
        return;
    }
    tbb::enumerable_thread_specific<Scratch> scratch;
    tbb::combinable<QueryCounters> per_thread;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tops, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        QueryCounters* c = kCount ? &per_thread.local() : nullptr;
        Walker<kOcclusion, kCount> walker(impl, rays, h, hits, occluded, scratch.local(), c);
        for (std::size_t j = r.begin(); j < r.end(); ++j) walker.top(j, object_spheres);
    });
    if constexpr (kCount) per_thread.combine_each([&](const QueryCounters& c) { *counters += c; });
}

template void traverse<false, false>(const Crsh::Impl&, bool, std::span<const Ray>, const RayHierarchy&, Hit*,
                                     std::uint8_t*, bool, QueryCounters*);
template void traverse<false, true>(const Crsh::Impl&, bool, std::span<const Ray>, const RayHierarchy&, Hit*,
                                    std::uint8_t*, bool, QueryCounters*);
template void traverse<true, false>(const Crsh::Impl&, bool, std::span<const Ray>, const RayHierarchy&, Hit*,
                                    std::uint8_t*, bool, QueryCounters*);
template void traverse<true, true>(const Crsh::Impl&, bool, std::span<const Ray>, const RayHierarchy&, Hit*,
                                   std::uint8_t*, bool, QueryCounters*);

}  // namespace beamtrace::crsh
