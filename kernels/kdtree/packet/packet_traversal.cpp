#include "kdtree/packet/packet_traversal.hpp"

#include <cfloat>
#include <cmath>

#include "beamtrace/error.hpp"
#include "common/interval.hpp"
#include "common/ray_validity.hpp"
#include "common/triangle_kernels.hpp"
#include "common/watertight_ray.hpp"
#include "kdtree/packet/lane_box_test.hpp"
#include "kdtree/packet/one_origin_frustum.hpp"
#include "kdtree/packet/packet_bounds.hpp"
#include "kdtree/packet/packet_lanes.hpp"
#include "kdtree/ray_traversal.hpp"

namespace beamtrace::kdtree {

namespace {

static_assert(kMaxTogether <= BlockBounds::kPackets, "a block's bounds hold every packet traced together");

constexpr int kStackSize = 64;
constexpr int kMailboxSize = 64;
// Leaves with at most this many triangles test them without frustum culling: deciding a batch
// costs about as much as a few packet tests, and the triangles of small leaves (walls, large
// faces) are seldom outside a packet's frustum (room, 1024x1024: 9.76 -> 9.87 tests per packet,
// about 6% less time).
constexpr std::uint32_t kMinCulledLeaf = 4;

struct StackEntry {
    std::uint32_t node;
    float c0, c1;
};

}  // namespace

TraversalStart root_start(const KdTree::Impl& kd) { return TraversalStart{NodeBox{0, kd.bounds}, nullptr}; }

namespace {

// One packet in an interval traversal: its lanes, their bounds, their set-up for the leaf tests,
// how far they still look, and its mailbox. A traversal carries one (trace_packet) or several
// (trace_packets_together), all of one sign octant.
struct TracedPacket {
    const Packet16* packet = nullptr;
    PacketHits16* hits = nullptr;
    std::uint32_t* occluded = nullptr;
    const float* speed = nullptr;
    PacketBounds pb;  // of this packet's lanes (test (2) at a leaf)
    float reach = -kInfinity;  // the farthest distance along its line any active lane may still hit at
    OneOriginFrustum frustum;
    WatertightPacket16 wp;
    LaneBoxRays box_rays;
    std::uint32_t mailbox[kMailboxSize];
};

// The largest tfar * |dir| over the lanes, widened; how far the packet still looks.
inline float farthest(const PacketTraversalContext& c, const TracedPacket& t) {
    const float d = c.tables.kernels->setup.farthest_distance(t.wp.tfar, t.speed, t.wp.active);
    return d + std::fabs(d) * kRelativePad;
}

// The lanes `mask` of a packet (one sign octant, no zero direction component) cut to the start cell
// and set up for the leaf tests, with its outputs. False when no lane meets the cell. The interval of
// distances at which its lanes cross the cell (widened) goes to *interval.
[[gnu::always_inline]] inline bool begin_packet(const PacketTraversalContext& c, const Packet16& packet, std::uint32_t mask,
                                                const Box& cell, const float* speed, PacketHits16* hits,
                                                std::uint32_t* occluded, TracedPacket& t, Interval* interval) {
    PacketBounds& pb = t.pb;
    pb.pad = c.tables.pad;
    {
        const int first = __builtin_ctz(mask);
        pb.sign[0] = std::signbit(packet.dir_x[first]) ? -1 : 1;
        pb.sign[1] = std::signbit(packet.dir_y[first]) ? -1 : 1;
        pb.sign[2] = std::signbit(packet.dir_z[first]) ? -1 : 1;
    }
    // Cell decisions use each ray's distance along its line (t * |dir|), so that rays of one
    // direction but different parameter speeds (shadow rays of different lengths) share intervals;
    // triangle tests keep each ray's own t. The lanes' cuts to the start cell, all at once.
    const PacketSetupKernels& setup = c.tables.kernels->setup;
    const CellEntry entry = setup.enter_cell(packet, mask, speed, cell, pb.pad);
    if (entry.lanes == 0) return false;
    const Interval cut = widen({entry.c0, entry.c1}, pb.pad);
    *interval = {std::max(cut.lo, entry.near - std::fabs(entry.near) * kRelativePad), cut.hi};
    for (int k = 0; k < 3; ++k) {
        pb.org[k] = entry.org[k];
        pb.inv[k] = entry.inv[k];
    }
    t.packet = &packet;
    t.hits = hits;
    t.occluded = occluded;
    t.speed = speed;
    t.frustum = OneOriginFrustum{};
    if (c.triangle_culling) t.frustum = setup.frustum(packet, entry.lanes);
    setup.watertight(packet, t.wp);
    t.wp.active = entry.lanes;
    setup.box_rays(packet, pb.pad, t.box_rays);
    for (std::uint32_t& b : t.mailbox) b = kNoHit;
    t.reach = farthest(c, t);
    return true;
}

// A leaf (`index`, entered at distance c0) for one packet: test (2) of its geometry box against the
// packet's bounds, the per-lane box test, frustum culling of its triangles, the 16-ray tests. Hits
// and occlusion bits go to the packet's outputs and its reach shrinks as rays find hits; false when
// the packet has no active lane left (occlusion).
template <bool kOcclusion, bool kCount>
[[gnu::always_inline]] inline bool visit_leaf(const PacketTraversalContext& c, std::uint32_t index, float c0, TracedPacket& t,
                bool bounds_tested, QueryCounters* counters) {
    const KdTree::Impl& kd = c.kd;
    const KdNode& node = kd.nodes[index];
    const std::uint32_t count = node.triangle_count();
    if (count == 0) return true;
    // The leaf's geometry (its triangles clipped to its cell: tighter than the cell, and what
    // a hit that matters lies in) against the packet's interval bounds (test (2)), then
    // against each active ray's current segment.
    const PacketKernels& packet_kernels = *c.tables.kernels;
    const Box& box = c.tables.geometry_boxes[index];
    if ((!bounds_tested && packet_misses_box(t.pb, box, c0, t.reach)) ||
        packet_kernels.lane_box(t.box_rays, t.wp.tfar, t.wp.active, box) == 0)
        return true;
    const TriangleKernels& kernels = *kd.kernels;
    const std::uint32_t* leaf = kd.triangle_ids.data() + node.offset();
    const Triangle* corners = kd.leaf_triangles.data() + node.offset();
    std::uint32_t culled = 0;  // bit j % 16: the packet's frustum misses leaf[j]
    const bool cull = t.frustum.valid && count > kMinCulledLeaf;
    bool shorter = false;  // some lane's segment got shorter: the reach is computed again after the leaf
    for (std::uint32_t j = 0; j < count; ++j) {
        if (cull && j % 16 == 0)  // the next 16 triangles decided at once (SIMD, from the corner rows)
            culled = packet_kernels.frustum_cull(t.frustum, c.tables.rows(), node.offset() + j,
                                                 int(std::min<std::uint32_t>(16, count - j)));
        const std::uint32_t id = leaf[j];
        std::uint32_t& slot = t.mailbox[id % kMailboxSize];
        if (slot == id) continue;  // already tested for every lane: the result cannot change
        slot = id;                 // a culled triangle stays culled: the frustum is the packet's
        if (cull && ((culled >> (j % 16)) & 1u)) continue;
        if constexpr (kCount) ++counters->triangle_tests;
        LaneHits lanes;
        // A culled leaf's corners come from the rows the culling has just read (in cache), others from
        // the leaf's triangles: the same values.
        if (cull)
            kernels.packet_x1(t.wp, c.tables.rows().triangle(node.offset() + j), lanes);
        else
            kernels.packet_x1(t.wp, corners[j], lanes);
        if constexpr (kOcclusion) {
            if (lanes.mask) {
                *t.occluded |= lanes.mask;
                t.wp.active &= ~lanes.mask;
                if (t.wp.active == 0) {
                    t.reach = -kInfinity;
                    return false;
                }
                shorter = true;
            }
        } else {
            for (std::uint32_t b = lanes.mask; b; b &= b - 1) {
                const int i = __builtin_ctz(b);
                if (lanes.t[i] < t.hits->t[i]) {
                    t.hits->t[i] = lanes.t[i];
                    t.hits->triangle[i] = id;
                    t.hits->u[i] = lanes.u[i];
                    t.hits->v[i] = lanes.v[i];
                    t.wp.tfar[i] = lanes.t[i];
                    shorter = true;
                }
            }
        }
    }
    // Read only by the decisions between leaves (test (2), the cells skipped beyond every lane's end).
    if (shorter) t.reach = farthest(c, t);
    return true;
}

// Interval traversal of packets[0 .. n) (each begun by begin_packet, all of one sign octant) as one:
// one interval [c0, c1] for all of them, bounded by the hull `pb` of their bounds and entered at
// the hull [e0, e1] of their cells' cuts, one stack; at each leaf every packet that still looks
// that far is tested by itself (visit_leaf).
template <bool kOcclusion, bool kCount>
void interval_traversal(const PacketTraversalContext& c, TracedPacket* packets, int n, const PacketBounds& pb,
                        float e0, float e1, const TraversalStart& start, QueryCounters* counters) {
    const KdNode* nodes = c.kd.nodes.data();
    const Box* geometry_boxes = c.tables.geometry_boxes.data();
    // Cells starting beyond the farthest any active ray still needs to look are skipped.
    auto reach_of_all = [&] {
        float r = -kInfinity;
        for (int p = 0; p < n; ++p) r = std::max(r, packets[p].reach);
        return r;
    };
    float reach = reach_of_all();
    float c0 = e0, c1 = e1;
    BlockBounds block;  // the packets' own bounds, for test (2) of all of them at once
    if (n > 1) {
        for (int k = 0; k < 3; ++k) block.sign[k] = pb.sign[k];
        block.pad = pb.pad;
        block.count = n;
        for (int p = 0; p < n; ++p) block.set(p, packets[p].pb, packets[p].reach);
    }
    StackEntry stack[kStackSize];
    int top = 0;
    std::uint32_t index = start.at.node;
    const TraversalResume* resume = start.resume;
    if (resume && resume->sign[0] == pb.sign[0] && resume->sign[1] == pb.sign[1] && resume->sign[2] == pb.sign[2]) {
        // Start at the resume leaf (for MLRTA: the entry-point search's first potential leaf): the
        // cells before it in this depth-first order hold nothing for the packets. What is left after
        // it is the other child of each bifurcation on its path, deepest on top, each with the
        // packets' interval over its box (the faces of a cell are the start node's and the splits
        // on its path, so this is the interval the walk would have reached it with, or tighter, and
        // as conservative). A child whose interval is empty holds no ray of the packets.
        auto interval = [&](const Box& b, float& a0, float& a1) {
            a0 = e0;
            a1 = e1;
            for (int k = 0; k < 3; ++k) {
                a0 = std::max(a0, pb.entry_t(b, k).lo);
                a1 = std::min(a1, pb.exit_t(b, k).hi);
            }
        };
        for (int i = 0; i < resume->count; ++i) {
            if constexpr (kCount) ++counters->packet_steps;
            const NodeBox& other = resume->path[i].other;
            float a0, a1;
            interval(other.box, a0, a1);
            if (a0 <= a1) stack[top++] = StackEntry{other.node, a0, a1};
        }
        index = resume->first.node;
        interval(resume->first.box, c0, c1);
    }
    for (;;) {
        const KdNode& node = nodes[index];
        if constexpr (kCount) ++counters->packet_steps;
        if (!node.is_leaf()) {
            const int k = node.axis();
            const Interval tp = pb.plane_t(k, node.split);
            const bool lower_near = pb.sign[k] > 0;
            const std::uint32_t lower = index + 1, upper = node.upper_child();
            const std::uint32_t near = lower_near ? lower : upper, far = lower_near ? upper : lower;
            if (c1 < tp.lo) {  // every ray leaves the cell before reaching the plane
                index = near;
            } else if (c0 > tp.hi) {  // every ray reaches the cell only beyond the plane
                index = far;
            } else {
                stack[top++] = StackEntry{far, std::max(c0, tp.lo), c1};
                c1 = std::min(c1, tp.hi);
                index = near;
            }
            // The next node's geometry box (read if it is a leaf) loads along with the node.
            __builtin_prefetch(geometry_boxes + index);
            continue;
        }
        if (node.triangle_count() > 0) {
            if (n == 1) {
                if (!visit_leaf<kOcclusion, kCount>(c, index, c0, packets[0], false, counters)) return;
                reach = packets[0].reach;
            } else if (const Box& box = geometry_boxes[index]; !packet_misses_box(pb, box, c0, reach)) {
                // Test (2) of every packet at once, then the packets that pass, one by one.
                const std::uint32_t meeting = c.tables.kernels->block_meeting(block, box, c0);
                for (std::uint32_t m = meeting; m; m &= m - 1) {
                    const int p = __builtin_ctz(m);
                    visit_leaf<kOcclusion, kCount>(c, index, c0, packets[p], true, counters);
                    block.reach[p] = packets[p].reach;
                }
                // Only the packets visited can look less far; their reaches are in one row.
                if (meeting != 0) {
                    reach = block.reach[0];
                    for (int p = 1; p < n; ++p) reach = std::max(reach, block.reach[p]);
                }
                if (reach == -kInfinity) return;  // occlusion: every ray of every packet stopped
            }
        }
        for (;;) {
            if (top == 0) return;
            const StackEntry& e = stack[--top];
            if (e.c0 > reach) continue;
            index = e.node;
            c0 = e.c0;
            c1 = e.c1;
            break;
        }
    }
}

// The lanes of `packet` selected by `mask` (one sign octant, no zero direction component) from
// `start`; speed[i] is the length of lane i's direction.
template <bool kOcclusion, bool kCount>
void trace_lanes(const PacketTraversalContext& c, const Packet16& packet, std::uint32_t mask, const TraversalStart& start,
                 const float* speed, PacketHits16* hits, std::uint32_t* occluded, QueryCounters* counters) {
    TracedPacket t;
    Interval interval;
    if (!begin_packet(c, packet, mask, start.at.box, speed, hits, occluded, t, &interval)) return;
    interval_traversal<kOcclusion, kCount>(c, &t, 1, t.pb, interval.lo, interval.hi, start, counters);
}

// Whether a group of rays travels together: its origins lie within 1% of the scene's diagonal and
// its rays are close enough to parallel for interval traversal: every component
// of the unit directions within kMaxSpread (about 3 degrees), and no component varying by more than a
// factor kMaxRatio. Otherwise the group's interval bounds cover the whole hull of a widening beam (or
// lose all precision for rays nearly parallel to a plane), and interval traversal visits far more
// cells than the rays one by one would.
bool travels_together(const GroupRanges& g, const KdTree::Impl& kd) {
    Box origins;
    origins.lower = Float3{g.org[0].lo, g.org[1].lo, g.org[2].lo};
    origins.upper = Float3{g.org[0].hi, g.org[1].hi, g.org[2].hi};
    if (origins.diagonal() > 0.01f * kd.bounds.diagonal()) return false;
    constexpr float kMaxSpread = 0.05f, kMaxRatio = 8.0f;
    for (int k = 0; k < 3; ++k) {
        // One sign per axis in a group: the magnitudes' range follows from the range.
        const Interval u = g.unit[k];
        const float alo = std::min(std::fabs(u.lo), std::fabs(u.hi)), ahi = std::max(std::fabs(u.lo), std::fabs(u.hi));
        if (u.hi - u.lo > kMaxSpread || ahi > kMaxRatio * alo) return false;
    }
    return true;
}

// One lane by the single-ray kd-tree traversal.
template <bool kOcclusion, bool kCount>
void trace_single(const PacketTraversalContext& c, const Packet16& packet, int i, PacketHits16* hits,
                  std::uint32_t* occluded, QueryCounters* counters) {
    if constexpr (kCount) ++counters->single_rays;
    const Ray r = packet.ray(i);
    if constexpr (kOcclusion) {
        if (occluded_one(c.kd, r)) *occluded |= 1u << i;
    } else {
        hits->set_hit(i, intersect_one(c.kd, r));
    }
}

}  // namespace

namespace {

// A packet's outputs cleared (no hit, nothing occluded), and the packet counted.
template <bool kOcclusion, bool kCount>
void clear_packet(PacketHits16* hits, std::uint32_t* occluded, QueryCounters* counters) {
    if constexpr (!kOcclusion) {
        for (int i = 0; i < 16; ++i) hits->set_hit(i, Hit{});
    } else {
        *occluded = 0;
    }
    if constexpr (kCount) ++counters->packets;
}

// The lanes with a zero (or denormal) direction component, which have no usable reciprocal, one by one.
template <bool kOcclusion, bool kCount>
void trace_flat_lanes(const PacketTraversalContext& c, const Packet16& packet, const PacketLanes& lanes_of,
                      PacketHits16* hits, std::uint32_t* occluded, QueryCounters* counters) {
    for (std::uint32_t b = lanes_of.flat; b; b &= b - 1)
        trace_single<kOcclusion, kCount>(c, packet, __builtin_ctz(b), hits, occluded, counters);
}

// trace_packet once the packet's lanes are known (lanes_of = packet_lanes(packet)) and its outputs
// cleared.
template <bool kOcclusion, bool kCount>
void trace_packet_lanes(const PacketTraversalContext& c, const Packet16& packet, const PacketLanes& lanes_of,
                        const TraversalStart& start, PacketHits16* hits, std::uint32_t* occluded,
                        QueryCounters* counters) {
    // Rays that describe no segment (NaN, infinities, a zero direction, tnear > tfar) report nothing;
    // zero (or denormal) components have no usable reciprocal: such rays go alone.
    trace_flat_lanes<kOcclusion, kCount>(c, packet, lanes_of, hits, occluded, counters);
    const std::uint32_t coherent = lanes_of.valid & ~lanes_of.flat;
    // Interval traversal pays when the rays of a group travel together. Groups of one or two rays,
    // groups whose origins lie far apart and groups of diverging or nearly plane-parallel directions
    // (incoherent secondary rays) are traced ray by ray.
    for (int o = 0; o < 8 && coherent; ++o) {
        const std::uint32_t lanes = octant_lanes(lanes_of, coherent, o);
        if (lanes == 0) continue;
        if (__builtin_popcount(lanes) > 2 &&
            travels_together(c.tables.kernels->setup.group_ranges(packet, lanes_of, lanes), c.kd)) {
            trace_lanes<kOcclusion, kCount>(c, packet, lanes, start, lanes_of.speed, hits, occluded, counters);
            continue;
        }
        for (std::uint32_t b = lanes; b; b &= b - 1)
            trace_single<kOcclusion, kCount>(c, packet, __builtin_ctz(b), hits, occluded, counters);
    }
}

}  // namespace

template <bool kOcclusion, bool kCount>
void trace_packet(const PacketTraversalContext& c, const Packet16& packet, const TraversalStart& start,
                  PacketHits16* hits, std::uint32_t* occluded, QueryCounters* counters) {
    clear_packet<kOcclusion, kCount>(hits, occluded, counters);
    if (packet.active == 0) return;
    // Direction lengths, unit directions and lane classes of all lanes at once.
    PacketLanes lanes_of;
    c.tables.kernels->setup.lanes(packet, lanes_of);
    trace_packet_lanes<kOcclusion, kCount>(c, packet, lanes_of, start, hits, occluded, counters);
}

template <bool kOcclusion, bool kCount>
void trace_packets_together(const PacketTraversalContext& c, const Packet16* const* packets, int n,
                            const TraversalStart& start, PacketHits16* const* hits, std::uint32_t* const* occluded,
                            QueryCounters* counters) {
    if (n < 1 || n > kMaxTogether) throw Error("trace_packets_together: between 1 and 16 packets");
    if (n == 1)
        return trace_packet<kOcclusion, kCount>(c, *packets[0], start, kOcclusion ? nullptr : hits[0],
                                                kOcclusion ? occluded[0] : nullptr, counters);
    auto hits_of = [&](int p) { return kOcclusion ? nullptr : hits[p]; };
    auto occluded_of = [&](int p) { return kOcclusion ? occluded[p] : nullptr; };
    // Together only when every packet's valid lanes, but for those with a zero direction component,
    // share one sign octant; the group's origins and unit directions pass the same tests as a
    // packet's group (trace_packet). Otherwise packet by packet, with the lanes found here.
    const PacketSetupKernels& setup = c.tables.kernels->setup;
    PacketLanes lanes_of[kMaxTogether];
    std::uint32_t coherent[kMaxTogether];
    int octant = -1, rays = 0;
    bool together = true;
    GroupRanges all;
    for (int p = 0; p < n; ++p) {
        setup.lanes(*packets[p], lanes_of[p]);
        coherent[p] = lanes_of[p].valid & ~lanes_of[p].flat;
        if (coherent[p] == 0 || !together) continue;
        const PacketLanes& l = lanes_of[p];
        const int i = __builtin_ctz(coherent[p]);
        const int o = int(((l.negative[0] >> i) & 1u) | (((l.negative[1] >> i) & 1u) << 1) | (((l.negative[2] >> i) & 1u) << 2));
        if ((octant >= 0 && o != octant) || octant_lanes(l, coherent[p], o) != coherent[p]) {
            together = false;
            continue;
        }
        octant = o;
        const GroupRanges g = setup.group_ranges(*packets[p], l, coherent[p]);
        if (rays == 0) {
            all = g;
        } else {
            for (int k = 0; k < 3; ++k) {
                all.org[k] = hull(all.org[k], g.org[k]);
                all.unit[k] = hull(all.unit[k], g.unit[k]);
            }
        }
        rays += __builtin_popcount(coherent[p]);
    }
    together = together && rays > 2 && travels_together(all, c.kd);
    if (!together) {
        for (int p = 0; p < n; ++p) {
            clear_packet<kOcclusion, kCount>(hits_of(p), occluded_of(p), counters);
            trace_packet_lanes<kOcclusion, kCount>(c, *packets[p], lanes_of[p], start, hits_of(p), occluded_of(p),
                                                   counters);
        }
        return;
    }
    TracedPacket traced[kMaxTogether];
    int m = 0;
    PacketBounds pb;
    float e0 = kInfinity, e1 = -kInfinity;
    for (int p = 0; p < n; ++p) {
        clear_packet<kOcclusion, kCount>(hits_of(p), occluded_of(p), counters);
        trace_flat_lanes<kOcclusion, kCount>(c, *packets[p], lanes_of[p], hits_of(p), occluded_of(p), counters);
        if (coherent[p] == 0) continue;
        TracedPacket& t = traced[m];
        Interval interval;
        if (!begin_packet(c, *packets[p], coherent[p], start.at.box, lanes_of[p].speed, hits_of(p), occluded_of(p), t,
                          &interval))
            continue;
        e0 = std::min(e0, interval.lo);
        e1 = std::max(e1, interval.hi);
        if (m == 0) {
            pb = t.pb;
        } else {
            for (int k = 0; k < 3; ++k) {
                pb.org[k] = hull(pb.org[k], t.pb.org[k]);
                pb.inv[k] = hull(pb.inv[k], t.pb.inv[k]);
            }
        }
        ++m;
    }
    if (m > 0) interval_traversal<kOcclusion, kCount>(c, traced, m, pb, e0, e1, start, counters);
}

#define BEAMTRACE_TRACE_PACKET(kOcclusion, kCount)                                                       \
    template void trace_packet<kOcclusion, kCount>(const PacketTraversalContext&, const Packet16&,       \
                                                   const TraversalStart&, PacketHits16*, std::uint32_t*, \
                                                   QueryCounters*);
BEAMTRACE_TRACE_PACKET(false, false)
BEAMTRACE_TRACE_PACKET(false, true)
BEAMTRACE_TRACE_PACKET(true, false)
BEAMTRACE_TRACE_PACKET(true, true)
#undef BEAMTRACE_TRACE_PACKET

#define BEAMTRACE_TRACE_TOGETHER(kOcclusion, kCount)                                                              \
    template void trace_packets_together<kOcclusion, kCount>(const PacketTraversalContext&, const Packet16* const*, \
                                                             int, const TraversalStart&, PacketHits16* const*,      \
                                                             std::uint32_t* const*, QueryCounters*);
BEAMTRACE_TRACE_TOGETHER(false, false)
BEAMTRACE_TRACE_TOGETHER(false, true)
BEAMTRACE_TRACE_TOGETHER(true, false)
BEAMTRACE_TRACE_TOGETHER(true, true)
#undef BEAMTRACE_TRACE_TOGETHER

}  // namespace beamtrace::kdtree
