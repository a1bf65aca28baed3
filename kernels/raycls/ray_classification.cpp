// RayClassification (beamtrace/ray_classification.hpp): the 5D tree, light buffers around shared
// points, and the query contract over them.
#include "beamtrace/ray_classification.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <vector>

#include "beamtrace/error.hpp"
#include "common/access.hpp"
#include "common/query_runner.hpp"
#include "common/ray_validity.hpp"
#include "kdtree/packet/packet_kernels.hpp"
#include "kdtree/ray_traversal.hpp"
#include "raycls/candidate_tests.hpp"
#include "raycls/occlusion_runs.hpp"
#include "raycls/cell_tree.hpp"
#include "raycls/shared_point.hpp"

namespace beamtrace {

using raycls::CellTree;
using raycls::DirectionCode;

void RayClsSettings::validate() const {
    if (max_depth < 0 || max_depth > 12)
        throw Error("ray classification: max_depth must be 0 (automatic) to 12, not " + std::to_string(max_depth));
    if (light_buffer_max_depth < 0 || light_buffer_max_depth > 20)
        throw Error("ray classification: light_buffer_max_depth must be 0 (automatic) to 20, not " +
                    std::to_string(light_buffer_max_depth));
    if (min_candidates < 0)
        throw Error("ray classification: min_candidates must be at least 0, not " + std::to_string(min_candidates));
    if (entries_per_ray < 0)
        throw Error("ray classification: entries_per_ray must be at least 0, not " + std::to_string(entries_per_ray));
    if (rays_per_new_cell < 1)
        throw Error("ray classification: rays_per_new_cell must be at least 1, not " +
                    std::to_string(rays_per_new_cell));
}

namespace {

// Light buffers kept at once (a call around a new point beyond this uses the 5D tree).
constexpr std::size_t kMaxLightBuffers = 64;
// Span calls shorter than this never make a light buffer (a single ray shares its own point).
constexpr std::size_t kMinLightBufferRays = 64;
// The 5D tree's payoff check: per window of this many rays of a thread, when more than
// kFallbackRatio times as many rays fell back to the kd-tree (their cell missing) as reached a cell,
// the call makes no more cells (incoherent rays: the cells they would need cost more than they save).
constexpr std::uint32_t kPayoffWindow = 4096;
constexpr std::uint32_t kFallbackRatio = 4;

int log2_ceil(double x) { return x <= 1.0 ? 0 : int(std::ceil(std::log2(x))); }

}  // namespace

struct RayClassification::Impl {
    KdTree tree;
    RayClsSettings settings;
    const TriangleKernels* kernels = nullptr;
    const kdtree::PacketSetupKernels* setup = nullptr;  // of the triangle kernels' instruction set
    int space_depth = 5, light_depth = 8;
    int light_first_list_depth = 1;  // light buffers' cells above it hold no list (docs/raycls.md)
    float scene_scale = 1.0f;     // largest coordinate magnitude of the tree's box
    float shared_point_size = 0;  // largest box of shared points
    float apex_margin = 0;        // light buffers' apex: the points' box grown by this
    mutable raycls::CellContext context;
    std::unique_ptr<CellTree> space;
    mutable std::mutex buffers_mutex;
    mutable std::vector<std::unique_ptr<CellTree>> buffers;
    mutable std::shared_mutex use_mutex;  // queries share it; pruning and clear() take it alone

    Impl(const KdTree& t, const RayClsSettings& s) : tree(t), settings(s) {
        settings.validate();
        const KdTree::Impl& ti = detail::Access::impl(tree);
        kernels = ti.kernels ? ti.kernels : &triangle_kernels();
        setup = &simd::select<kdtree::PacketKernels>(kernels->isa).setup;
        const std::size_t n = std::max<std::size_t>(1, ti.scene.triangle_count());
        space_depth = settings.max_depth ? settings.max_depth : std::clamp((log2_ceil(double(n)) + 2) / 3, 5, 8);
        light_depth = settings.light_buffer_max_depth ? settings.light_buffer_max_depth
                                                      : std::clamp((log2_ceil(double(n) / 6.0) + 1) / 2 + 2, 6, 14);
        // Lists start where a cell holds about 4,096 candidates (a face's quarter holds a 24th of the scene).
        light_first_list_depth = std::clamp(int(std::lround(std::log2(double(n) / 24576.0) / 2.0)), 1, light_depth);
        const Box& b = ti.bounds;
        for (int k = 0; k < 3; ++k)
            scene_scale = std::max(scene_scale, std::max(std::fabs(b.lower[k]), std::fabs(b.upper[k])));
        shared_point_size = b.diagonal() * raycls::kSharedPointFraction;
        apex_margin = b.diagonal() * raycls::kApexMarginFraction;
        context.tree = &ti;
        context.min_candidates = settings.min_candidates;
        context.memory_budget = settings.memory_budget_bytes;
        context.capped = settings.entries_per_ray > 0;
        // Rounding of the points rays are classified from (float sums of the scene's magnitude) and
        // of the direction codes (one division, |u| <= 1): both far below the margins.
        context.origin_margin = double(scene_scale) * 1e-5;
        context.direction_margin = 1e-6;
        space = std::make_unique<CellTree>(context, b, true, space_depth, 1, settings.rays_per_new_cell);
    }

    // A call of `rays` rays starts: the work cap grows; cells are freed while no call runs, down to
    // half the budget when over it.
    void start_call(std::size_t rays) const {
        context.epoch.fetch_add(1, std::memory_order_relaxed);
        context.growth_stopped.store(false, std::memory_order_relaxed);
        context.entry_allowance.fetch_add(std::uint64_t(rays) * std::uint64_t(settings.entries_per_ray),
                                          std::memory_order_relaxed);
        // A cell dropped for the budget in the last call asks for room as well as bytes over it.
        const bool full = context.budget_full.exchange(false, std::memory_order_relaxed);
        if (settings.memory_budget_bytes == 0 || (!full && context.bytes.load() <= settings.memory_budget_bytes))
            return;
        std::unique_lock<std::shared_mutex> alone(use_mutex, std::try_to_lock);
        if (!alone.owns_lock()) return;
        std::vector<const CellTree*> trees{space.get()};
        for (const auto& b : buffers) trees.push_back(b.get());
        raycls::prune(context, trees, settings.memory_budget_bytes / 2);
    }

    // The light buffer whose apex box holds `points`, made when there is none (nullptr when too many).
    const CellTree* light_buffer(const Box& points) const {
        std::lock_guard<std::mutex> lock(buffers_mutex);
        for (const auto& b : buffers)
            if (b->origins().contains(points)) return b.get();
        if (buffers.size() >= kMaxLightBuffers) return nullptr;
        // A little room around the points, so that later calls around the same point reuse it.
        Box apex = points;
        const float grow = apex_margin;
        apex.lower = apex.lower - Float3{grow, grow, grow};
        apex.upper = apex.upper + Float3{grow, grow, grow};
        buffers.push_back(std::make_unique<CellTree>(context, apex, false, light_depth, light_first_list_depth, 1));
        return buffers.back().get();
    }
};

namespace {

using Impl = RayClassification::Impl;

using raycls::Frame;
using raycls::origin_of;

// Runs of one light buffer open at once (OcclusionRuns): a ray joins the open run of its grid cell,
// or takes the place of the run opened longest ago (traced first). Image-order shadow rays visit a
// few cells in turn; with 16 open runs 80 % of room's shadow rays go in runs of at least four, with
// one 69 % (docs/raycls.md).
constexpr std::size_t kOpenRuns = 16;

// Light buffers one call may use (rays sharing up to this many end or start points: shadow rays
// towards a few point lights); a call whose rays share more points uses the 5D tree.
constexpr std::size_t kMaxCallPoints = 16;

// Where a call's rays are classified: the 5D tree, or one light buffer per shared point (`of`: ray i's
// buffer, empty when there is one).
struct CallPlan {
    Frame frame = Frame::space;
    std::vector<const CellTree*> cells;
    std::vector<std::uint8_t> of;

    std::size_t cells_of(std::size_t ray) const { return of.empty() ? 0 : of[ray]; }
};

// Shared end points (occlusion only: classified from the lights) or shared start points, each with
// its light buffer; else the 5D tree.
CallPlan plan_call(const Impl& impl, std::span<const Ray> rays, bool occlusion) {
    CallPlan plan{Frame::space, {impl.space.get()}, {}};
    if (!impl.settings.light_buffers) return plan;
    raycls::SharedPoints shared = raycls::find_shared_points(rays, occlusion, impl.shared_point_size,
                                                             kMinLightBufferRays, kMaxCallPoints);
    if (shared.frame == Frame::space) return plan;
    std::vector<const CellTree*> buffers;
    for (const Box& points : shared.points) {
        const CellTree* t = impl.light_buffer(points);
        if (!t) return plan;  // too many light buffers kept: the 5D tree
        buffers.push_back(t);
    }
    return CallPlan{shared.frame, std::move(buffers), std::move(shared.of)};
}

// Rays of one thread that reached a cell and that fell back to the kd-tree, per window of one call
// (kept per thread across the call's chunks: a chunk of a threaded call is shorter than a window).
struct Payoff {
    const void* owner = nullptr;
    std::uint64_t epoch = 0;
    std::uint32_t reached = 0, fell_back = 0;

    void start(const void* classification, std::uint64_t call) {
        if (owner != classification || epoch != call) *this = Payoff{classification, call, 0, 0};
    }

    // At the end of a window: stops the call's growth when cells do not pay.
    void check(raycls::CellContext& context) {
        if (reached + fell_back < kPayoffWindow) return;
        if (fell_back > kFallbackRatio * reached && !context.growth_stopped.exchange(true, std::memory_order_relaxed))
            context.growth_stops.fetch_add(1, std::memory_order_relaxed);
        reached = fell_back = 0;
    }
};

// Where a ray's answer comes from: its cell's candidates (and how far along them to look), or an
// answer already (a ray that describes no segment; the kd-tree's, when the memory budget leaves no
// room for its cell).
struct Located {
    bool answered = false;
    Hit answer;
    std::span<const raycls::Candidate> items;
    float key_origin = 0.0f, step = 0.0f;  // closest hits: a hit at t lies at key key_origin + t * step
    float stop = 0.0f;                     // occlusion: candidates with keys beyond it need no test
};

// A ray's cell (the part's cache first).
template <bool kOcclusion, bool kCount>
Located locate(const Impl& impl, Frame frame, const CellTree& cells, const Ray& r, const raycls::Cell*& cache,
               QueryCounters* counters, Payoff& payoff) {
    Located at;
    at.answered = true;
    if (!describes_segment(r)) return at;
    const Ray& ray = r;
    float p[3];
    DirectionCode code;
    if (frame == Frame::space) {
        // The part of the segment inside the scene's box, classified from where it enters.
        const Box& box = cells.origins();
        const Float3 inv{1.0f / r.dir.x, 1.0f / r.dir.y, 1.0f / r.dir.z};
        float tmin, tmax;
        if (!kdtree::clip_to_box(r, inv, box, tmin, tmax)) return at;
        for (int k = 0; k < 3; ++k) p[k] = std::clamp(r.org[k] + tmin * r.dir[k], box.lower[k], box.upper[k]);
        code = raycls::direction_code(r.dir);
    } else if (frame == Frame::from_start) {
        for (int k = 0; k < 3; ++k) p[k] = origin_of(r, k);
        code = raycls::direction_code(r.dir);
    } else {
        for (int k = 0; k < 3; ++k) p[k] = 0.0f;  // not read: a light buffer's origins are not split
        code = raycls::direction_code(Float3{-r.dir.x, -r.dir.y, -r.dir.z});
    }
    if constexpr (kCount) {
        ++counters->raycls.rays;
        if (frame != Frame::space) ++counters->raycls.light_buffer_rays;
    }
    const raycls::Cell* cell = nullptr;
    if (cache && raycls::cell_contains(cache->bounds, p, code.face, code.u, code.v, frame == Frame::space)) {
        cell = cache;
        if constexpr (kCount) ++counters->raycls.cache_hits;
    } else {
        cell = cells.find<kCount>(p, code, counters);
        if (!cell) {
            ++payoff.fell_back;
            const KdTree::Impl& tree = detail::Access::impl(impl.tree);
            at.answer = kdtree::traverse_ray<kOcclusion, kCount, !kOcclusion>(tree, ray, counters);
            return at;
        }
        if (impl.settings.cache) cache = cell;
    }
    ++payoff.reached;
    at.answered = false;
    at.items = cell->grid ? cell->grid->cell(code.u, code.v) : std::span<const raycls::Candidate>(cell->list.items);
    const int k = raycls::face_axis(code.face);
    const float s = float(raycls::face_sign(code.face));
    at.key_origin = s * r.org[k];
    at.step = std::fabs(r.dir[k]);
    if constexpr (kOcclusion) {
        if (frame == Frame::from_end)
            at.stop = raycls::key_stop(at.key_origin, -r.tnear, at.step);  // the segment's start, seen from the light
        else
            at.stop = raycls::key_stop(at.key_origin, r.tfar, at.step);
    }
    return at;
}

// One ray: its cell, then its candidates.
template <bool kOcclusion, bool kCount>
Hit trace_one(const Impl& impl, Frame frame, const CellTree& cells, const Ray& r, const raycls::Cell*& cache,
              QueryCounters* counters, Payoff& payoff) {
    const Located at = locate<kOcclusion, kCount>(impl, frame, cells, r, cache, counters, payoff);
    if (at.answered) return at.answer;
    if constexpr (kOcclusion)
        return raycls::any_hit(raycls::any_candidate<kCount>(*impl.kernels, at.items, r, at.stop, counters));
    else
        return raycls::closest_candidate<kCount>(*impl.kernels, at.items, r, at.key_origin, at.step, counters);
}

template <bool kOcclusion, class Out>
void trace_span(const Impl& impl, std::span<const Ray> rays, const QueryOptions& options, Out&& out) {
    impl.start_call(rays.size());
    std::shared_lock<std::shared_mutex> use(impl.use_mutex);
    const CallPlan plan = plan_call(impl, rays, kOcclusion);
    const std::uint64_t call = impl.context.epoch.load(std::memory_order_relaxed);
    run_query(rays.size(), options, 1024, [&](std::size_t b, std::size_t e, QueryCounters* c) {
        const raycls::Cell* caches[kMaxCallPoints] = {};  // the last cell of each light buffer
        thread_local Payoff payoff;
        payoff.start(&impl, call);
        const bool watch = plan.frame == Frame::space;
        if (kOcclusion && !watch && impl.settings.packet_light_buffers) {
            // kOpenRuns runs per light buffer (the rays of several lights come interleaved).
            const auto runs = [&](auto count, QueryCounters* counters) {
                using Runs = raycls::OcclusionRuns<decltype(count)::value, decltype(out)>;
                constexpr std::size_t K = kOpenRuns;
                std::vector<Runs> run;
                run.reserve(plan.cells.size() * K);
                for (std::size_t t = 0; t < plan.cells.size() * K; ++t)
                    run.emplace_back(*impl.kernels, *impl.setup, out, counters);
                std::vector<std::uint8_t> next(plan.cells.size(), 0);
                for (std::size_t i = b; i < e; ++i) {
                    const std::size_t t = plan.cells_of(i);
                    const Located at = locate<true, decltype(count)::value>(impl, plan.frame, *plan.cells[t], rays[i],
                                                                            caches[t], counters, payoff);
                    if (at.answered) {
                        out(i, at.answer);
                        continue;
                    }
                    Runs* open = run.data() + t * K;
                    std::size_t k = 0;
                    while (k < K && !open[k].holds(at.items)) ++k;
                    if (k == K) {
                        k = next[t];
                        next[t] = std::uint8_t((k + 1) % K);
                        open[k].flush();
                    }
                    open[k].add(i, rays[i], at.items, at.stop);
                }
                for (Runs& r : run) r.flush();
            };
            if (c)
                runs(std::true_type{}, c);
            else
                runs(std::false_type{}, nullptr);
            return;
        }
        for (std::size_t i = b; i < e; ++i) {
            const std::size_t t = plan.cells_of(i);
            const CellTree& cells = *plan.cells[t];
            out(i, c ? trace_one<kOcclusion, true>(impl, plan.frame, cells, rays[i], caches[t], c, payoff)
                     : trace_one<kOcclusion, false>(impl, plan.frame, cells, rays[i], caches[t], nullptr, payoff));
            if (watch) payoff.check(impl.context);
        }
    });
}

// The lanes of packets as rays (inactive lanes: rays that describe no segment).
std::vector<Ray> packet_rays(std::span<const Packet16> packets) {
    std::vector<Ray> rays(packets.size() * 16);
    for (std::size_t p = 0; p < packets.size(); ++p)
        for (int i = 0; i < 16; ++i)
            rays[p * 16 + std::size_t(i)] =
                ((packets[p].active >> i) & 1u) ? packets[p].ray(i) : Ray{{0, 0, 0}, 0.0f, {0, 0, 0}, 0.0f};
    return rays;
}

}  // namespace

RayClassification::RayClassification(const Scene& scene, const RayClsSettings& settings, const KdBuildRules& rules)
    : RayClassification(KdTree::build(scene, rules), settings) {}

RayClassification::RayClassification(const KdTree& tree, const RayClsSettings& settings)
    : impl_(std::make_shared<Impl>(tree, settings)) {}

Hit RayClassification::intersect(const Ray& ray) const {
    impl_->start_call(1);
    std::shared_lock<std::shared_mutex> use(impl_->use_mutex);
    const raycls::Cell* cache = nullptr;
    Payoff payoff;
    return trace_one<false, false>(*impl_, Frame::space, *impl_->space, ray, cache, nullptr, payoff);
}

bool RayClassification::occluded(const Ray& ray) const {
    impl_->start_call(1);
    std::shared_lock<std::shared_mutex> use(impl_->use_mutex);
    const raycls::Cell* cache = nullptr;
    Payoff payoff;
    return trace_one<true, false>(*impl_, Frame::space, *impl_->space, ray, cache, nullptr, payoff)
        .hit();
}

void RayClassification::intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options) const {
    check_query("RayClassification::intersect", rays.size(), hits.size(), options);
    trace_span<false>(*impl_, rays, options, [&](std::size_t i, const Hit& h) { hits[i] = h; });
}

void RayClassification::occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded,
                                 const QueryOptions& options) const {
    check_query("RayClassification::occluded", rays.size(), occluded.size(), options);
    trace_span<true>(*impl_, rays, options, [&](std::size_t i, const Hit& h) { occluded[i] = h.hit() ? 1 : 0; });
}

void RayClassification::intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                                  const QueryOptions& options) const {
    check_query("RayClassification::intersect", packets.size(), hits.size(), options);
    const std::vector<Ray> rays = packet_rays(packets);
    trace_span<false>(*impl_, rays, options, [&](std::size_t i, const Hit& h) { hits[i / 16].set_hit(int(i % 16), h); });
}

void RayClassification::occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                                 const QueryOptions& options) const {
    check_query("RayClassification::occluded", packets.size(), occluded.size(), options);
    std::vector<std::uint8_t> any(packets.size() * 16);
    const std::vector<Ray> rays = packet_rays(packets);
    trace_span<true>(*impl_, rays, options, [&](std::size_t i, const Hit& h) { any[i] = h.hit() ? 1 : 0; });
    for (std::size_t p = 0; p < packets.size(); ++p) {
        std::uint32_t bits = 0;
        for (int i = 0; i < 16; ++i) bits |= std::uint32_t(any[p * 16 + std::size_t(i)]) << i;
        occluded[p] = bits;
    }
}

void RayClassification::clear() const {
    std::unique_lock<std::shared_mutex> alone(impl_->use_mutex);
    std::lock_guard<std::mutex> lock(impl_->buffers_mutex);
    impl_->buffers.clear();
    raycls::prune(impl_->context, {impl_->space.get()}, 0);
    impl_->context.cells_created = 0;
    impl_->context.entries_made = 0;
    impl_->context.entry_allowance = 0;
    impl_->context.cells_freed = 0;
    impl_->context.build_ns = 0;
    impl_->context.max_depth_reached = 0;
    impl_->context.growth_stops = 0;
    impl_->context.peak_bytes = impl_->context.bytes.load();
}

const Scene& RayClassification::scene() const { return impl_->tree.scene(); }
const KdTree& RayClassification::kd_tree() const { return impl_->tree; }
const RayClsSettings& RayClassification::settings() const { return impl_->settings; }

RayClsStats RayClassification::stats() const {
    const raycls::CellContext& c = impl_->context;
    RayClsStats s;
    s.cells_created = c.cells_created.load();
    s.cells_freed = c.cells_freed.load();
    s.candidate_entries = c.entries.load();
    {
        std::lock_guard<std::mutex> lock(impl_->buffers_mutex);
        s.light_buffers = impl_->buffers.size();
    }
    s.memory_bytes = c.bytes.load();
    s.memory_peak_bytes = c.peak_bytes.load();
    s.lazy_build_seconds = double(c.build_ns.load()) * 1e-9;
    s.max_depth_reached = c.max_depth_reached.load();
    s.growth_stops = c.growth_stops.load();
    return s;
}

}  // namespace beamtrace
