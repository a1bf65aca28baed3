// The packet walk of the wide BVH (wide_bvh_packet.hpp).
#include "bvh/wide_bvh_packet.hpp"

#include <algorithm>
#include <cmath>

#include <xsimd/xsimd.hpp>

#include "bvh/wide_bvh_traversal.hpp"
#include "common/ray_validity.hpp"
#include "common/triangle_kernels.hpp"
#include "common/watertight_ray.hpp"
#include "kdtree/packet/packet_kernels.hpp"
#include "kdtree/packet/packet_lanes.hpp"

namespace beamtrace::bvh {

bool packet_bounds_reference(const Packet16& p, std::uint32_t lanes, const float* const inv[3], PacketBounds& b) {
    if (lanes == 0) return false;
    const float* org[3] = {p.org_x, p.org_y, p.org_z};
    const float* dir[3] = {p.dir_x, p.dir_y, p.dir_z};
    // Lanes not in `lanes` take the first live lane's values (they change no minimum or maximum);
    // then every loop below is over 16 lanes without a branch.
    const int first = __builtin_ctz(lanes);
    alignas(64) float tn[16], tf[16], o[3][16], v[3][16], d[3][16];
    for (int i = 0; i < 16; ++i) {
        const int k = ((lanes >> i) & 1u) ? i : first;
        tn[i] = p.tnear[k];
        tf[i] = p.tfar[k];
        for (int a = 0; a < 3; ++a) {
            o[a][i] = org[a][k];
            v[a][i] = inv[a][k];
            d[a][i] = dir[a][k];
        }
    }
    // Forward (f) and reversed (r: from the far ends back) at once, four lanes a step (the library's
    // baseline); reversed only with finite ends.
    using B = xsimd::batch<float, xsimd::sse4_2>;
    const auto lowest = [](const B& x) {
        alignas(16) float t[4];
        x.store_aligned(t);
        return std::min(std::min(t[0], t[1]), std::min(t[2], t[3]));
    };
    const auto highest = [](const B& x) {
        alignas(16) float t[4];
        x.store_aligned(t);
        return std::max(std::max(t[0], t[1]), std::max(t[2], t[3]));
    };
    PacketBounds f, r;
    {
        B lo = B::load_aligned(tn), hi = B::load_aligned(tf), len(0.0f);
        for (int i = 0; i < 16; i += 4) {
            const B n = B::load_aligned(tn + i), e = B::load_aligned(tf + i);
            lo = xsimd::min(lo, n);
            hi = xsimd::max(hi, e);
            len = xsimd::max(len, (e - n) * B(1.0f + kBoxSlack));
        }
        f.tnear = lowest(lo);
        f.tfar = highest(hi);
        r.tnear = 0.0f;
        r.tfar = highest(len);
    }
    bool finite = std::isfinite(r.tfar);
    for (int a = 0; a < 3; ++a) {
        B ilo_b = B::load_aligned(v[a]), ihi_b = ilo_b, olo_b = B::load_aligned(o[a]), ohi_b = olo_b;
        B elo_b(kInfinity), ehi_b(-kInfinity);
        for (int i = 0; i < 16; i += 4) {
            const B vi = B::load_aligned(v[a] + i), oi = B::load_aligned(o[a] + i);
            ilo_b = xsimd::min(ilo_b, vi);
            ihi_b = xsimd::max(ihi_b, vi);
            olo_b = xsimd::min(olo_b, oi);
            ohi_b = xsimd::max(ohi_b, oi);
            // The far end, rounded twice: widened by far more than both roundings.
            const B step = B::load_aligned(tf + i) * B::load_aligned(d[a] + i);
            const B end = oi + step;
            const B err = (xsimd::abs(oi) + B(2.0f) * xsimd::abs(step)) * B(1.0f / 4194304.0f);
            elo_b = xsimd::min(elo_b, end - err);
            ehi_b = xsimd::max(ehi_b, end + err);
        }
        if (!set_axis_bounds(a, lowest(ilo_b), highest(ihi_b), lowest(olo_b), highest(ohi_b), lowest(elo_b),
                             highest(ehi_b), f, r, finite))
            return false;
    }
    b = tighter_bounds(f, r, finite);
    return true;
}

std::uint32_t packet_node_reference(const PacketBounds& b, const WideNode& n, int children) {
    std::uint32_t bits = 0;
    for (int c = 0; c < children; ++c) {
        float entry = b.tnear, exit = b.tfar;
        for (int a = 0; a < 3; ++a) {
            const float near_plane = b.upper_first[a] ? n.upper[a][c] : n.lower[a][c];
            const float far_plane = b.upper_first[a] ? n.lower[a][c] : n.upper[a][c];
            const float n0 = near_plane - b.org_hi[a], n1 = near_plane - b.org_lo[a];
            const float f0 = far_plane - b.org_hi[a], f1 = far_plane - b.org_lo[a];
            const float near_min =
                std::min(std::min(n0 * b.inv_lo[a], n0 * b.inv_hi[a]), std::min(n1 * b.inv_lo[a], n1 * b.inv_hi[a]));
            const float far_max =
                std::max(std::max(f0 * b.inv_lo[a], f0 * b.inv_hi[a]), std::max(f1 * b.inv_lo[a], f1 * b.inv_hi[a]));
            entry = std::max(entry, near_min);
            exit = std::min(exit, far_max);
        }
        if (entry - std::fabs(entry) * kBoxSlack <= exit + std::fabs(exit) * kBoxSlack) bits |= 1u << c;
    }
    return bits;
}

std::uint32_t packet_leaf_reference(const PacketBounds& b, const float* block, int count) {
    alignas(64) WideNode boxes;
    for (int a = 0; a < 3; ++a)
        for (int i = 0; i < count; ++i) {
            const std::size_t n = std::size_t(count), k = std::size_t(i);
            const float c0 = block[std::size_t(a) * n + k], c1 = block[std::size_t(3 + a) * n + k],
                        c2 = block[std::size_t(6 + a) * n + k];
            boxes.lower[a][i] = std::min(std::min(c0, c1), c2);
            boxes.upper[a][i] = std::max(std::max(c0, c1), c2);
        }
    return packet_node_reference(b, boxes, count);
}

namespace {

// The triangle of lane i of a leaf's corner block.
Triangle leaf_triangle(const float* block, std::size_t count, std::size_t i) {
    Triangle t;
    float* v = &t.v0.x;
    for (std::size_t c = 0; c < 9; ++c) v[c] = block[c * count + i];
    return t;
}

// The walk of the lanes `active` (their bounds made), as occluded_packet describes it.
std::uint32_t walk_packet(const WideBvh& bvh, const Packet16& p, std::uint32_t active, const PacketBounds& bounds,
                          const kdtree::LaneBoxRays& box_rays, WatertightPacket16& w, const WideBvhKernels& kernels,
                          const kdtree::PacketKernels& packet, const TriangleKernels& triangles,
                          QueryCounters* counters) {
    // A stack entry: a child and the live rays whose segments meet its box (the per-lane slab test,
    // made as it is pushed for each child the packet's bounds admit).
    struct Entry {
        std::uint32_t ref, lanes;
    };
    Entry stack[WideBvh::kMaxDepth * (kWidth - 1) + 1];
    int top = 0;
    std::uint32_t occluded = 0;
    {
        const std::uint32_t lanes = packet.lane_box(box_rays, p.tfar, active, bvh.bounds);
        if (lanes != 0) stack[top++] = Entry{bvh.root, lanes};
    }
    while (top != 0) {
        const Entry e = stack[--top];
        std::uint32_t lanes = e.lanes & ~occluded;
        if (lanes == 0) continue;
        if (!is_leaf(e.ref)) {
            if (counters) ++counters->packet_steps;
            const WideNode& node = bvh.nodes[node_index(e.ref)];
            for (std::uint32_t bits = kernels.packet_node(bounds, node, node_children(e.ref)); bits != 0;
                 bits &= bits - 1) {
                const int c = __builtin_ctz(bits);
                Box box;
                box.lower = Float3{node.lower[0][c], node.lower[1][c], node.lower[2][c]};
                box.upper = Float3{node.upper[0][c], node.upper[1][c], node.upper[2][c]};
                const std::uint32_t meeting = packet.lane_box(box_rays, p.tfar, lanes, box);
                if (meeting != 0) stack[top++] = Entry{node.child[c], meeting};
            }
            continue;
        }
        const std::uint32_t first = leaf_first(e.ref);
        const std::size_t count = leaf_count(e.ref);
        if (counters) ++counters->leaves;
        const float* block = bvh.rows.data() + 9 * std::size_t(first);
        // The triangles' boxes against the packet's bounds: only those the bounds admit are tested.
        std::uint32_t admitted = kernels.packet_leaf(bounds, block, int(count));
        for (; admitted != 0 && lanes != 0; admitted &= admitted - 1) {
            const std::size_t i = std::size_t(__builtin_ctz(admitted));
            if (counters) ++counters->triangle_tests;
            w.active = lanes;
            LaneHits hits;
            triangles.packet_x1(w, leaf_triangle(block, count, i), hits);
            occluded |= hits.mask;
            lanes &= ~hits.mask;
        }
        if ((active & ~occluded) == 0) break;
    }
    return occluded;
}

}  // namespace

std::uint32_t occluded_packet(const WideBvh& bvh, const Packet16& p, Isa isa, QueryCounters* counters) {
    const WideBvhKernels& kernels = wide_bvh_kernels(isa);
    const std::uint32_t active = p.active & segment_lanes(p) & 0xFFFFu;
    if (counters) ++counters->packets;
    if (active == 0 || bvh.root == kEmpty) return 0;
    const kdtree::PacketKernels& packet = simd::select<kdtree::PacketKernels>(isa);
    alignas(64) kdtree::LaneBoxRays box_rays;
    packet.setup.box_rays(p, bvh.pad, box_rays);
    const float* const inv[3] = {box_rays.inv[0], box_rays.inv[1], box_rays.inv[2]};
    const TriangleKernels& triangles = triangle_kernels(isa);
    WatertightPacket16 w;
    PacketBounds bounds;
    if (kernels.packet_bounds(p, active, inv, bounds)) {
        packet.setup.watertight(p, w);
        return walk_packet(bvh, p, active, bounds, box_rays, w, kernels, packet, triangles, counters);
    }
    // The signs of the directions differ (or a component is 0 or not finite): the lanes of each
    // octant together when there are a few and they can be bounded, the others one by one.
    std::uint32_t negative[3] = {0, 0, 0};  // the reciprocals' sign bits (the directions', zeros' too)
    for (int k = 0; k < 3; ++k)
        for (std::uint32_t m = active; m != 0; m &= m - 1)
            if (std::signbit(inv[k][__builtin_ctz(m)])) negative[k] |= 1u << __builtin_ctz(m);
    bool set_up = false;
    std::uint32_t occluded = 0, alone = 0;
    for (int o = 0; o < 8; ++o) {
        const std::uint32_t same = kdtree::octant_lanes(negative, active, o);
        if (same == 0) continue;
        if (__builtin_popcount(same) >= 4 && kernels.packet_bounds(p, same, inv, bounds)) {
            if (!set_up) packet.setup.watertight(p, w);
            set_up = true;
            occluded |= walk_packet(bvh, p, same, bounds, box_rays, w, kernels, packet, triangles, counters);
        } else {
            alone |= same;
        }
    }
    for (std::uint32_t m = alone; m != 0; m &= m - 1) {
        const int i = __builtin_ctz(m);
        if (counters) ++counters->single_rays;
        const Hit h = counters ? kernels.occluded_counted(bvh, p.ray(i), counters) : kernels.occluded(bvh, p.ray(i));
        if (h.hit()) occluded |= 1u << i;
    }
    return occluded;
}

}  // namespace beamtrace::bvh
