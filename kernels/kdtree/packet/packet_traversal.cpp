#include "kdtree/packet/packet_traversal.hpp"

#include <cfloat>
#include <cmath>

#include "common/interval.hpp"
#include "common/ray_validity.hpp"
#include "common/triangle_kernels.hpp"
#include "common/watertight_ray.hpp"
#include "kdtree/packet/lane_box_test.hpp"
#include "kdtree/packet/one_origin_frustum.hpp"
#include "kdtree/packet/packet_lanes.hpp"
#include "kdtree/ray_traversal.hpp"

namespace beamtrace::kdtree {

namespace {

constexpr int kStackSize = 64;
constexpr int kMailboxSize = 64;
// Leaves with at most this many triangles test them without frustum culling: deciding a batch
// costs about as much as a few packet tests, and the triangles of small leaves (walls, large
// faces) are seldom outside a packet's frustum (room, 1024x1024: 9.76 -> 9.87 tests per packet,
// about 6% less time).
constexpr std::uint32_t kMinCulledLeaf = 4;

// The packet's bounds used to derive every plane interval: origins and reciprocal directions per
// axis over the active lanes.
struct PacketBounds {
    Interval org[3];
    Interval inv[3];
    int sign[3];
    float pad;

    // Range of t at which the active rays cross the plane x_k = p, widened outwards.
    Interval plane_t(int k, float p) const {
        const Interval offset = widen({p - org[k].hi, p - org[k].lo}, pad);
        return widen(offset * inv[k], pad);
    }
    // The same at the face of `box` on axis k where the rays enter its slab, and where they leave it.
    Interval entry_t(const Box& box, int k) const { return plane_t(k, sign[k] > 0 ? box.lower[k] : box.upper[k]); }
    Interval exit_t(const Box& box, int k) const { return plane_t(k, sign[k] > 0 ? box.upper[k] : box.lower[k]); }
};

// Test (2) of section 3.3 for the packet against a box, limited to parameters in [t0, t1].
bool packet_misses_box(const PacketBounds& pb, const Box& box, float t0, float t1) {
    Interval entry[3], exit[3];
    for (int k = 0; k < 3; ++k) {
        entry[k] = pb.entry_t(box, k);
        exit[k] = pb.exit_t(box, k);
        if (exit[k].hi < t0 || entry[k].lo > t1) return true;
    }
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            if (a != b && entry[a].lo > exit[b].hi) return true;
    return false;
}

struct StackEntry {
    std::uint32_t node;
    float c0, c1;
};

}  // namespace

TraversalStart root_start(const KdTree::Impl& kd) { return TraversalStart{NodeBox{0, kd.bounds}, nullptr}; }

namespace {

// Traces the lanes of `packet` selected by `mask` (one sign octant, no zero direction component)
// from `start`; speed[i] is the length of lane i's direction. Closest hits go to `hits` lanes; for
// occlusion, bits are or-ed into *occluded.
template <bool kOcclusion, bool kCount>
void interval_traversal(const PacketTraversalContext& c, const Packet16& packet, std::uint32_t mask,
                        const TraversalStart& start, const float* speed, PacketHits16* hits, std::uint32_t* occluded,
                        QueryCounters* counters) {
    const KdTree::Impl& kd = c.kd;
    const PacketKernels& packet_kernels = *c.tables.kernels;
    PacketBounds pb;
    pb.pad = c.tables.pad;
    {
        const int first = __builtin_ctz(mask);
        pb.sign[0] = std::signbit(packet.dir_x[first]) ? -1 : 1;
        pb.sign[1] = std::signbit(packet.dir_y[first]) ? -1 : 1;
        pb.sign[2] = std::signbit(packet.dir_z[first]) ? -1 : 1;
    }
    // Cell decisions use each ray's distance along its line (t * |dir|), so that rays of one
    // direction but different parameter speeds (shadow rays of different lengths) share intervals;
    // triangle tests keep each ray's own t. The lanes' cuts to the entry point's cell, all at once.
    const CellEntry entry = enter_cell(packet, mask, speed, start.at.box, pb.pad);
    mask = entry.lanes;
    if (mask == 0) return;
    for (int k = 0; k < 3; ++k) {
        pb.org[k] = entry.org[k];
        pb.inv[k] = entry.inv[k];
    }
    float c0, c1;
    {
        const Interval cell = widen({entry.c0, entry.c1}, pb.pad);
        c0 = std::max(cell.lo, entry.near - std::fabs(entry.near) * kRelativePad);
        c1 = cell.hi;
    }
    // The farthest distance along its line any active ray may still hit at (its tfar or closest hit).
    // It only changes when a ray finds a hit (or, for occlusion, stops), so it is kept, not recomputed
    // per cell.
    auto farthest = [&](std::uint32_t lanes, const float* tfar) {
        const float d = farthest_distance(tfar, speed, lanes);
        return d + std::fabs(d) * kRelativePad;
    };

    OneOriginFrustum frustum;
    if (c.triangle_culling) frustum = make_one_origin_frustum(packet, mask);
    WatertightPacket16 wp = make_watertight_packet(packet);
    wp.active = mask;
    const LaneBoxRays box_rays = make_lane_box_rays(packet, pb.pad);
    const TriangleKernels& kernels = *kd.kernels;
    const KdNode* nodes = kd.nodes.data();
    const std::uint32_t* ids = kd.triangle_ids.data();
    const Triangle* tris = kd.leaf_triangles.data();
    const CornerRows rows = c.tables.rows();
    std::uint32_t mailbox[kMailboxSize];
    for (std::uint32_t& b : mailbox) b = kNoHit;

    float reach = farthest(wp.active, wp.tfar);
    StackEntry stack[kStackSize];
    int top = 0;
    std::uint32_t index = start.at.node;
    const TraversalResume* resume = start.resume;
    if (resume && resume->sign[0] == pb.sign[0] && resume->sign[1] == pb.sign[1] && resume->sign[2] == pb.sign[2]) {
        // Start at the resume leaf (for MLRTA: the entry-point search's first potential leaf): the
        // cells before it in this depth-first order hold nothing for the packet. What is left after
        // it is the other child of each bifurcation on its path, deepest on top, each with the
        // packet's interval over its box (the faces of a cell are the start node's and the splits
        // on its path, so this is the interval the walk would have reached it with, or tighter, and
        // as conservative). A child whose interval is empty holds no ray of the packet.
        const float e0 = c0, e1 = c1;
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
            continue;
        }
        // The leaf's geometry (its triangles clipped to its cell: tighter than the cell, and what
        // a hit that matters lies in) against the packet's interval bounds (test (2)), then
        // against each active ray's current segment.
        const Box& box = c.tables.geometry_boxes[index];
        const std::uint32_t count = node.triangle_count();
        if (count > 0 && !packet_misses_box(pb, box, c0, reach) &&
            packet_kernels.lane_box(box_rays, wp.tfar, wp.active, box) != 0) {
            const std::uint32_t* leaf = ids + node.offset();
            const Triangle* corners = tris + node.offset();
            std::uint32_t culled = 0;  // bit j % 16: the packet's frustum misses leaf[j]
            const bool cull = frustum.valid && count > kMinCulledLeaf;
            for (std::uint32_t j = 0; j < count; ++j) {
                if (cull && j % 16 == 0)  // the next 16 triangles decided at once (SIMD, from the corner rows)
                    culled = packet_kernels.frustum_cull(frustum, rows, node.offset() + j,
                                                         int(std::min<std::uint32_t>(16, count - j)));
                const std::uint32_t id = leaf[j];
                std::uint32_t& slot = mailbox[id % kMailboxSize];
                if (slot == id) continue;  // already tested for every lane: the result cannot change
                const Triangle& tri = corners[j];
                if (cull) {
                    if ((culled >> (j % 16)) & 1u) {
                        slot = id;  // the frustum is the packet's: the triangle stays culled
                        continue;
                    }
                }
                slot = id;
                if constexpr (kCount) ++counters->triangle_tests;
                LaneHits lanes;
                kernels.packet_x1(wp, tri, lanes);
                if constexpr (kOcclusion) {
                    if (lanes.mask) {
                        *occluded |= lanes.mask;
                        wp.active &= ~lanes.mask;
                        if (wp.active == 0) return;
                        reach = farthest(wp.active, wp.tfar);
                    }
                } else {
                    bool nearer = false;
                    for (std::uint32_t b = lanes.mask; b; b &= b - 1) {
                        const int i = __builtin_ctz(b);
                        if (lanes.t[i] < hits->t[i]) {
                            hits->t[i] = lanes.t[i];
                            hits->triangle[i] = id;
                            hits->u[i] = lanes.u[i];
                            hits->v[i] = lanes.v[i];
                            wp.tfar[i] = lanes.t[i];
                            nearer = true;
                        }
                    }
                    if (nearer) reach = farthest(wp.active, wp.tfar);
                }
            }
        }
        // Cells starting beyond the farthest any active ray still needs to look are skipped.
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

// Whether the rays of a group are close enough to parallel for interval traversal: every component
// of the unit directions within kMaxSpread (about 3 degrees), and no component varying by more than a
// factor kMaxRatio. Otherwise the group's interval bounds cover the whole hull of a widening beam (or
// lose all precision for rays nearly parallel to a plane), and interval traversal visits far more
// cells than the rays one by one would.
bool well_conditioned(const GroupRanges& g) {
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

template <bool kOcclusion, bool kCount>
void trace_packet(const PacketTraversalContext& c, const Packet16& packet, const TraversalStart& start,
                  PacketHits16* hits, std::uint32_t* occluded, QueryCounters* counters) {
    if constexpr (!kOcclusion) {
        for (int i = 0; i < 16; ++i) hits->set_hit(i, Hit{});
    } else {
        *occluded = 0;
    }
    if constexpr (kCount) ++counters->packets;
    if (packet.active == 0) return;
    // Direction lengths, unit directions and lane classes of all lanes at once (SSE).
    const PacketLanes lanes_of = packet_lanes(packet);
    // Rays that describe no segment (NaN, infinities, a zero direction, tnear > tfar) report nothing;
    // zero (or denormal) components have no usable reciprocal: such rays go alone.
    for (std::uint32_t b = lanes_of.flat; b; b &= b - 1)
        trace_single<kOcclusion, kCount>(c, packet, __builtin_ctz(b), hits, occluded, counters);
    const std::uint32_t coherent = lanes_of.valid & ~lanes_of.flat;
    // Interval traversal pays when the rays of a group travel together. Groups of one or two rays,
    // groups whose origins lie far apart and groups of diverging or nearly plane-parallel directions
    // (incoherent secondary rays) are traced ray by ray.
    const float far_apart = 0.01f * c.kd.bounds.diagonal();
    for (int o = 0; o < 8 && coherent; ++o) {
        const std::uint32_t lanes = octant_lanes(lanes_of, coherent, o);
        if (lanes == 0) continue;
        bool together = __builtin_popcount(lanes) > 2;
        if (together) {
            const GroupRanges g = group_ranges(packet, lanes_of, lanes);  // origins and unit directions, one pass
            Box origins;
            origins.lower = Float3{g.org[0].lo, g.org[1].lo, g.org[2].lo};
            origins.upper = Float3{g.org[0].hi, g.org[1].hi, g.org[2].hi};
            together = !(origins.diagonal() > far_apart) && well_conditioned(g);
        }
        if (together) {
            interval_traversal<kOcclusion, kCount>(c, packet, lanes, start, lanes_of.speed, hits, occluded, counters);
            continue;
        }
        for (std::uint32_t b = lanes; b; b &= b - 1)
            trace_single<kOcclusion, kCount>(c, packet, __builtin_ctz(b), hits, occluded, counters);
    }
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

}  // namespace beamtrace::kdtree
