#pragma once
// The masked group traversal (group_traversal.hpp) written once over xsimd's Arch: an inner node is
// one step of 4, 8 or 16 lanes at a time (SSE4.2, AVX2, AVX-512), every lane doing the operations of
// the single-ray traversal's decision in the same order, so every width gives the same answers and
// counts bit for bit (GroupTraversal.EveryInstructionSetGivesTheSameAnswersBitForBit). Included only
// by the per-ISA units (simd/kernels_<isa>.cpp), which put GroupLanes<Arch>::trace in their
// GroupKernels tables.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "common/ray_validity_impl.hpp"
#include "common/triangle_kernels.hpp"
#include "common/watertight_packet_impl.hpp"
#include "kdtree/ray_traversal.hpp"
#include "kdtree/packet/packet_tables.hpp"
#include "simd/lane_bits.hpp"
#include "simd/lane_folds.hpp"
#include "stream/group_traversal.hpp"

namespace beamtrace::stream {

// Everything here is a template of the unit's Arch (no inline function of external linkage compiled
// for a wider instruction set can be linked into a narrower unit); a lane's single-ray set-up comes
// from group_lane_ray, compiled once.
namespace group_detail {

constexpr int kStackSize = 64;

struct alignas(64) Intervals {
    float tmin[16], tmax[16];
};

struct StackEntry {
    std::uint32_t node;
    std::uint32_t lanes;
    Intervals t;
};

// The group's rays in the layout the steps read.
struct GroupRays {
    const float* org[3];
    const float* dir[3];
    alignas(64) float inv[3][16];
};

// One inner node for every lane in `lanes`: the single-ray traversal's decisions lane by lane. The
// group goes on into `near` (the lower child when lower_first), whose lanes and intervals replace
// `t` in place; the other child's go to `far`. Returns the lanes going near; far_lanes those going
// far.
// kOneOrigin: every lane starts at lane `lead`'s origin, which does not lie in the plane (the
// distance to the plane and the side are then the same for all lanes: computed once).
template <class Arch, bool kOneOrigin>
[[gnu::always_inline]] inline std::uint32_t split_lanes(const GroupRays& g, Intervals& t, std::uint32_t lanes, int axis,
                                                        float split_at, bool lower_first, Intervals& far,
                                                        std::uint32_t& far_lanes) {
    using B = xsimd::batch<float, Arch>;
    using M = xsimd::batch_bool<float, Arch>;
    constexpr int W = int(B::size);
    constexpr std::uint32_t kBlock = (1u << W) - 1u;
    const B split(split_at), ulp(1.0f / 1048576.0f), zero(0.0f);
    const M all = zero == zero, none = zero != zero;
    const M near_is_lower = lower_first ? all : none;
    const int lead = __builtin_ctz(lanes);
    const B to_plane(split_at - g.org[axis][lead]);
    const M lead_below = g.org[axis][lead] < split_at ? all : none;
    std::uint32_t near_lanes = 0;
    far_lanes = 0;
    for (int base = 0; base < 16; base += W) {
        if (((lanes >> base) & kBlock) == 0) continue;
        const B tmin = B::load_aligned(t.tmin + base), tmax = B::load_aligned(t.tmax + base);
        B tp;
        M lower_side;
        // The lower child first: the origin below the plane, or in it going up; a plane crossed
        // behind the origin swaps the order.
        if constexpr (kOneOrigin) {
            tp = to_plane * B::load_aligned(g.inv[axis] + base);
            lower_side = lead_below;
        } else {
            const B o = B::load_unaligned(g.org[axis] + base), d = B::load_unaligned(g.dir[axis] + base);
            tp = (split - o) * B::load_aligned(g.inv[axis] + base);
            lower_side = (o < split) | ((o == split) & (d > zero));
        }
        // lower_side xor behind, without ^ or != (xsimd 8.1's AVX-512 batch_bool ^ computes |, and
        // its SSE and AVX != compares the masks as floats, NaN patterns: always true).
        const M behind = tp < zero;
        const M first_lower = (lower_side & ~behind) | (~lower_side & behind);
        const M second_lower = ~first_lower;
        const M visits_first = ~(tp < tmin - xsimd::abs(tmin) * ulp);
        const M visits_second = ~(tp > tmax + xsimd::abs(tmax) * ulp);
        const M both = visits_first & visits_second & (tp == tp);
        const M lower = (first_lower & visits_first) | (second_lower & visits_second);
        const M upper = (first_lower & visits_second) | (second_lower & visits_first);
        const M on = simd::lanes_on<Arch>(lanes >> base);
        const B lo_min = xsimd::select(both & second_lower, tp, tmin),
                lo_max = xsimd::select(both & first_lower, tp, tmax);
        const B up_min = xsimd::select(both & first_lower, tp, tmin),
                up_max = xsimd::select(both & second_lower, tp, tmax);
        const std::uint32_t lower_bits = simd::lane_bits<Arch>(lower & on),
                            upper_bits = simd::lane_bits<Arch>(upper & on);
        near_lanes |= (lower_first ? lower_bits : upper_bits) << base;
        far_lanes |= (lower_first ? upper_bits : lower_bits) << base;
        xsimd::select(near_is_lower, lo_min, up_min).store_aligned(t.tmin + base);
        xsimd::select(near_is_lower, lo_max, up_max).store_aligned(t.tmax + base);
        xsimd::select(near_is_lower, up_min, lo_min).store_aligned(far.tmin + base);
        xsimd::select(near_is_lower, up_max, lo_max).store_aligned(far.tmax + base);
    }
    return near_lanes;
}

// Whether lane i meets the lower child first (the single-ray traversal's order for that lane).
template <class Arch>
bool lower_first_for(const GroupRays& g, int i, int axis, float split) {
    const float o = g.org[axis][i], d = g.dir[axis][i];
    const float tp = (split - o) * g.inv[axis][i];
    const bool lower_side = o < split || (o == split && d > 0.0f);
    return lower_side != (tp < 0.0f);
}

// Lanes whose interval starts beyond their closest hit (with the traversal's slack) leave.
template <class Arch>
std::uint32_t lanes_before(const Intervals& t, const float* best, std::uint32_t lanes) {
    using B = xsimd::batch<float, Arch>;
    constexpr int W = int(B::size);
    constexpr std::uint32_t kBlock = (1u << W) - 1u;
    const B ulp(1.0f / 1048576.0f);
    std::uint32_t keep = 0;
    for (int base = 0; base < 16; base += W) {
        if (((lanes >> base) & kBlock) == 0) continue;
        const B b = B::load_aligned(best + base);
        keep |= simd::lane_bits<Arch>(~(B::load_aligned(t.tmin + base) > b + xsimd::abs(b) * ulp)) << base;
    }
    return keep & lanes;
}

template <class Arch, bool kOcclusion, bool kCount>
class GroupTrace {
public:
    GroupTrace(const KdTree::Impl& kd, const Packet16& group, PacketHits16* hits, std::uint32_t* occluded,
               QueryCounters* counters)
        : kd_(kd),
          group_(group),
          hits_(hits),
          occluded_(occluded),
          counters_(counters),
          kernels_(*kd.kernels),
          rows_(kd.packet_tables().rows()) {}

    void run() {
        if constexpr (kOcclusion)
            *occluded_ = 0;
        else
            for (int i = 0; i < 16; ++i) hits_->set_hit(i, Hit{});
        Intervals t;
        for (int k = 0; k < 3; ++k) {
            rays_.org[k] = k == 0 ? group_.org_x : k == 1 ? group_.org_y : group_.org_z;
            rays_.dir[k] = k == 0 ? group_.dir_x : k == 1 ? group_.dir_y : group_.dir_z;
        }
        const std::uint32_t lanes = start_lanes(t);
        if (lanes == 0) return;
        valid_ = lanes;
        Packet16 valid = group_;
        valid.active = lanes;
        simd_impl::make_watertight_packet<Arch>(valid, packet_);
        one_origin_ = packet_.same_origin;
        if (one_origin_) make_reach(lanes, t);
        traverse(lanes, t);
    }

private:
    // The lanes that start: active, describing a segment (describes_segment) and meeting the tree's box
    // (kdtree::clip_to_box, their intervals into t), W lanes a step with the scalar code's operations
    // lane by lane; every other lane gets harmless values (an empty interval at 0, closest hit 0,
    // reciprocals 1).
    std::uint32_t start_lanes(Intervals& t) {
        using B = xsimd::batch<float, Arch>;
        using M = xsimd::batch_bool<float, Arch>;
        constexpr int W = int(B::size);
        const B zero(0.0f), one(1.0f), slack(1.0f / 1048576.0f);
        const Box& box = kd_.bounds;
        std::uint32_t lanes = 0;
        for (int base = 0; base < 16; base += W) {
            const B o[3] = {B::load_unaligned(rays_.org[0] + base), B::load_unaligned(rays_.org[1] + base),
                            B::load_unaligned(rays_.org[2] + base)};
            const B d[3] = {B::load_unaligned(rays_.dir[0] + base), B::load_unaligned(rays_.dir[1] + base),
                            B::load_unaligned(rays_.dir[2] + base)};
            const B tnear = B::load_unaligned(group_.tnear + base), tfar = B::load_unaligned(group_.tfar + base);
            M start = simd::lanes_on<Arch>(group_.active >> base) &
                      simd::describes_segment_lanes<Arch>(o[0], o[1], o[2], d[0], d[1], d[2], tnear, tfar);
            B tmin = tnear, tmax = tfar, inv[3];
            for (int k = 0; k < 3; ++k) {
                inv[k] = one / d[k];
                const B lower(box.lower[k]), upper(box.upper[k]);
                const M flat = d[k] == zero;  // in the slab or out
                start = start & ~(flat & ((o[k] < lower) | (o[k] > upper)));
                const B t0 = (lower - o[k]) * inv[k], t1 = (upper - o[k]) * inv[k];
                const M swap = t0 > t1;
                B near = xsimd::select(swap, t1, t0), far = xsimd::select(swap, t0, t1);
                near = near - xsimd::abs(near) * slack;
                far = far + xsimd::abs(far) * slack;
                tmin = xsimd::select(flat, tmin, xsimd::select(near > tmin, near, tmin));
                tmax = xsimd::select(flat, tmax, xsimd::select(far < tmax, far, tmax));
            }
            start = start & (tmin <= tmax);
            xsimd::select(start, tmin, zero).store_aligned(t.tmin + base);
            xsimd::select(start, tmax, zero).store_aligned(t.tmax + base);
            xsimd::select(start, B(kInfinity), zero).store_aligned(best_ + base);
            for (int k = 0; k < 3; ++k) xsimd::select(start, inv[k], one).store_aligned(rays_.inv[k] + base);
            lanes |= simd::lane_bits<Arch>(start) << base;
        }
        return lanes;
    }

    // With one origin: the box every valid lane's segment lies in (its interval after the clip to the
    // tree's box), widened on each side by 2^-16 of its coordinates' size. The single-ray decision at
    // a plane beyond it is, for every lane, the origin's child alone with its interval unchanged (the
    // traversal's slack is 2^-20 of t, the plane distance's rounding a few 2^-24 of it; docs/streams.md,
    // "Planes no lane reaches"), so traverse goes there without a step. Left at -inf / +inf (no plane
    // skipped) for groups of several origins and for segments that are not finite.
    void make_reach(std::uint32_t lanes, const Intervals& t) {
        using B = xsimd::batch<float, Arch>;
        using M = xsimd::batch_bool<float, Arch>;
        constexpr int W = int(B::size);
        constexpr std::uint32_t kBlock = (1u << W) - 1u;
        const int lead = __builtin_ctz(lanes);
        for (int k = 0; k < 3; ++k) {
            const float o = rays_.org[k][lead];
            const B ob(o), zero(0.0f);
            simd::MinFold lo;
            simd::MaxFold hi;
            for (int base = 0; base < 16; base += W) {
                if (((lanes >> base) & kBlock) == 0) continue;
                const B d = B::load_unaligned(rays_.dir[k] + base);
                const M on = simd::lanes_on<Arch>(lanes >> base), moves = ~(d == zero);
                const B a = xsimd::select(moves, ob + B::load_aligned(t.tmin + base) * d, ob);
                const B b = xsimd::select(moves, ob + B::load_aligned(t.tmax + base) * d, ob);
                lo.add(xsimd::min(a, b), on);
                hi.add(xsimd::max(a, b), on);
            }
            const float l = std::min(o, lo.result()), h = std::max(o, hi.result());
            const float margin = (std::fabs(l) + std::fabs(h) + std::fabs(o)) * (1.0f / 65536.0f) + 1e-30f;
            const bool finite = std::isfinite(l) && std::isfinite(h) && std::isfinite(margin);
            reach_lo_[k] = finite ? l - margin : -INFINITY;
            reach_hi_[k] = finite ? h + margin : INFINITY;
        }
    }

    void traverse(std::uint32_t lanes, Intervals& t) {
        const KdNode* nodes = kd_.nodes.data();
        StackEntry stack[kStackSize];
        int top = 0;
        std::uint32_t index = 0;
        for (;;) {
            if (lanes != 0) {
                const KdNode& node = nodes[index];
                if (!node.is_leaf()) {
                    // A plane beyond every lane's segment: the origin's side, no step (make_reach).
                    const int axis = node.axis();
                    if (node.split > reach_hi_[axis] || node.split < reach_lo_[axis]) {
                        if constexpr (kCount) ++counters_->stream.group_unreached_planes;
                        index = node.split > reach_hi_[axis] ? index + 1 : node.upper_child();
                        continue;
                    }
                    if ((lanes & (lanes - 1)) == 0) {
                        // One lane left: it walks the subtree alone, one scalar step a node; then
                        // the stack.
                        go_alone(__builtin_ctz(lanes), index, t);
                        if constexpr (kOcclusion)
                            if (done_ == valid_) return;
                    } else {
                        if constexpr (kCount) ++counters_->stream.group_steps;
                        // Near: the child the leading lane meets first. The far child's lanes go on
                        // the stack (depth <= 60, KdBuildRules: it never overflows).
                        const bool lower_first = lower_first_for<Arch>(rays_, __builtin_ctz(lanes), axis, node.split);
                        StackEntry& far = stack[top];
                        std::uint32_t far_lanes = 0;
                        lanes = one_origin_ && rays_.org[axis][__builtin_ctz(lanes)] != node.split
                                    ? split_lanes<Arch, true>(rays_, t, lanes, axis, node.split, lower_first, far.t,
                                                              far_lanes)
                                    : split_lanes<Arch, false>(rays_, t, lanes, axis, node.split, lower_first, far.t,
                                                               far_lanes);
                        // Pushed without a branch (an entry without lanes is left behind at once).
                        far.node = lower_first ? node.upper_child() : index + 1;
                        far.lanes = far_lanes;
                        top += far_lanes != 0;
                        index = lower_first ? index + 1 : node.upper_child();
                        if (lanes != 0) continue;
                    }
                } else {
                    visit_leaf(index, lanes, t);
                    if constexpr (kOcclusion)
                        if (done_ == valid_) return;
                }
            }
            // The next cell from the stack, for the lanes still looking.
            for (;;) {
                if (top == 0) return;
                StackEntry& e = stack[--top];
                lanes = e.lanes & ~done_;
                if constexpr (!kOcclusion) lanes = lanes_before<Arch>(e.t, best_, lanes);
                if (lanes == 0) continue;
                index = e.node;
                t = e.t;
                break;
            }
        }
    }

    // Leaf `index` for `lanes` (their intervals in t): one 16-ray test a triangle when at least
    // kPacketTestLanes lanes reach it, else each lane alone (go_alone: the single-ray traversal's leaf
    // test, 16 triangles a call from the corner rows).
    void visit_leaf(std::uint32_t index, std::uint32_t lanes, const Intervals& t) {
        const KdNode& node = kd_.nodes[index];
        const std::uint32_t count = node.triangle_count();
        if (count == 0) return;
        if (__builtin_popcount(lanes) < kPacketTestLanes) {
            for (std::uint32_t m = lanes; m; m &= m - 1) go_alone(__builtin_ctz(m), index, t);
            return;
        }
        if constexpr (kCount) {
            ++counters_->stream.group_leaves;
            counters_->triangle_tests += count;
        }
        const std::uint32_t* ids = kd_.triangle_ids.data() + node.offset();
        const Triangle* tris = kd_.leaf_triangles.data() + node.offset();
        packet_.active = lanes;
        for (std::uint32_t j = 0; j < count; ++j) {
            LaneHits h;
            kernels_.packet_x1(packet_, tris[j], h);
            take(h, ids[j]);
            if constexpr (kOcclusion) {
                packet_.active &= ~h.mask;
                if (packet_.active == 0) break;
            }
        }
        packet_.active = group_active();
    }

    // Lane i, alone in the subtree at `node` with its interval in t: the single-ray traversal of that
    // subtree (kdtree::traverse_subtree, whose decisions the steps here repeat lane by lane), going
    // on from the lane's closest hit so far.
    void go_alone(int i, std::uint32_t node, const Intervals& t) {
        const Ray ray = group_.ray(i);
        const Float3 inv{rays_.inv[0][i], rays_.inv[1][i], rays_.inv[2][i]};  // 1 / dir, as the walk takes it
        const WatertightRay w = lane_ray(i);
        if constexpr (kOcclusion) {
            if (kdtree::traverse_subtree<true, kCount>(kd_, ray, inv, w, node, t.tmin[i], t.tmax[i], Hit{}, rows_.at,
                                                       rows_.stride, counters_)
                    .hit()) {
                done_ |= 1u << i;
                *occluded_ |= 1u << i;
            }
        } else {
            const Hit h = kdtree::traverse_subtree<false, kCount>(kd_, ray, inv, w, node, t.tmin[i], t.tmax[i],
                                                                  hits_->hit(i), rows_.at, rows_.stride, counters_);
            if (h.t < best_[i]) record(i, h.t, h.triangle, h.u, h.v);
        }
    }

    // Hits of a 16-ray test of triangle `id`.
    void take(const LaneHits& h, std::uint32_t id) {
        const std::uint32_t mask = h.mask;
        if constexpr (kOcclusion) {
            done_ |= mask;
            *occluded_ |= mask;
        } else {
            for (std::uint32_t b = mask; b; b &= b - 1) {
                const int i = __builtin_ctz(b);
                if (h.t[i] < best_[i]) record(i, h.t[i], id, h.u[i], h.v[i]);
            }
        }
    }

    void record(int i, float t, std::uint32_t id, float u, float v) {
        best_[i] = t;
        packet_.tfar[i] = t;
        hits_->set_hit(i, Hit{t, id, u, v});
    }

    // Lane i's set-up for the single-ray kernels, made on its first use (tfar: its closest hit).
    WatertightRay lane_ray(int i) {
        if (!((made_ >> i) & 1u)) {
            wrays_[i] = group_lane_ray(group_.ray(i));
            made_ |= 1u << i;
        }
        WatertightRay w = wrays_[i];
        w.tfar = packet_.tfar[i];
        return w;
    }

    std::uint32_t group_active() const { return valid_ & ~done_; }

    const KdTree::Impl& kd_;
    const Packet16& group_;
    PacketHits16* hits_;
    std::uint32_t* occluded_;
    QueryCounters* counters_;
    const TriangleKernels& kernels_;
    const kdtree::CornerRows rows_;  // the leaf triangles' corners as rows (kdtree/packet/packet_tables.hpp)
    GroupRays rays_{};
    WatertightPacket16 packet_;
    alignas(64) float best_[16] = {};  // a lane's closest hit so far: +inf before its first (a hit at t = tfar counts)
    std::uint32_t done_ = 0;
    std::uint32_t valid_ = 0;
    bool one_origin_ = false;                                // every valid lane starts at one point (bit for bit)
    float reach_lo_[3] = {-INFINITY, -INFINITY, -INFINITY};  // make_reach
    float reach_hi_[3] = {INFINITY, INFINITY, INFINITY};
    WatertightRay wrays_[16];
    std::uint32_t made_ = 0;  // lanes whose wrays_ entry is made
};

}  // namespace group_detail

template <class Arch>
struct GroupLanes {
    template <bool kOcclusion, bool kCount>
    static void trace(const KdTree::Impl& kd, const Packet16& group, PacketHits16* hits, std::uint32_t* occluded,
                      QueryCounters* counters) {
        group_detail::GroupTrace<Arch, kOcclusion, kCount>(kd, group, hits, occluded, counters).run();
    }
    static constexpr GroupKernels table(Isa isa) {
        return GroupKernels{isa, {{trace<false, false>, trace<false, true>}, {trace<true, false>, trace<true, true>}}};
    }
};

}  // namespace beamtrace::stream
