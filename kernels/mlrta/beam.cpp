#include "mlrta/beam.hpp"

#include <cmath>
#include <span>
#include <type_traits>

#include "common/ray_validity.hpp"
#include "simd/sse_lanes.hpp"

namespace beamtrace::mlrta {

namespace {

bool positive(float v) { return !std::signbit(v); }

void extend(Interval& i, float v, bool first) {
    if (first)
        i = {v, v};
    else
        i = {std::min(i.lo, v), std::max(i.hi, v)};
}

int dominant_axis(Float3 d) {
    const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
    return ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
}

}  // namespace

void Beam::add(const Ray& ray) {
    const bool first = empty;
    if (first) {
        for (int k = 0; k < 3; ++k) sign[k] = positive(ray.dir[k]) ? 1 : -1;
        coherent = true;
        main_axis = dominant_axis(ray.dir);
    }
    for (int k = 0; k < 3; ++k) {
        if (ray.dir[k] == 0.0f || (positive(ray.dir[k]) ? 1 : -1) != sign[k]) coherent = false;
    }
    starts.extend(ray.org + ray.dir * ray.tnear);
    if (first) {
        one_origin = true;
        origin = ray.org;
    } else if (!(ray.org == origin)) {
        one_origin = false;
    }
    if (coherent) {
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j) extend(slope[k][j], j == k ? 1.0f : ray.dir[j] / ray.dir[k], first);
        const float scale = std::fabs(ray.dir[main_axis]);
        extend(length, (ray.tfar - ray.tnear) * scale, first);
        extend(apex_near, ray.tnear * scale, first);
        extend(apex_far, ray.tfar * scale, first);
    }
    empty = false;
    ++rays;
}

namespace {

using Lanes = sse::Floats;  // the library's baseline instruction set
using LaneMask = sse::Mask;
using sse::bits_of;
using sse::lanes_on;
constexpr int kLanes = int(Lanes::size);

// Running minimum and maximum over the selected lanes of 16 values.
struct LaneRange {
    Lanes lo = Lanes(kInfinity), hi = Lanes(-kInfinity);
    void add(const LaneMask& on, const Lanes& v) {
        lo = xsimd::min(lo, xsimd::select(on, v, Lanes(kInfinity)));
        hi = xsimd::max(hi, xsimd::select(on, v, Lanes(-kInfinity)));
    }
    void add(const Lanes& v) {  // every lane on: the same values without the selects
        lo = xsimd::min(lo, v);
        hi = xsimd::max(hi, v);
    }
    Interval interval() const {
        alignas(16) float l[kLanes], h[kLanes];
        lo.store_aligned(l);
        hi.store_aligned(h);
        Interval r{l[0], h[0]};
        for (int i = 1; i < kLanes; ++i) r = {std::min(r.lo, l[i]), std::max(r.hi, h[i])};
        return r;
    }
};

}  // namespace

void Beam::add(const Packet16& packet) {
    const Packet16* one = &packet;
    add(std::span<const Packet16* const>(&one, 1));
}

void Beam::add(std::span<const Packet16* const> packets) {
    // Per-component ranges of the active rays (SSE, 4 lanes at a time) over every packet, reduced
    // once, then the slopes by interval division: looser than per-ray slopes but a few operations
    // per ray (this runs for every packet of every tile). Rays that describe no segment are traced
    // by nobody and must not widen (or poison) the beam: they are masked out, like inactive lanes.
    // Lengths are measured along the main axis of the first ray (any axis on which every ray has a
    // non-zero component will do; a ray with a zero one makes the beam incoherent).
    LaneRange d[3], s[3], len, near, far;
    std::uint32_t negative[3] = {0, 0, 0};
    bool zero = false, same_origin = true, any = false;
    int main_axis_of_beam = 0;
    Lanes lead_org[3];
    Float3 first_origin;
    std::uint32_t rays_added = 0;
    for (const Packet16* packet_ptr : packets) {
        const Packet16& packet = *packet_ptr;
        const std::uint32_t active = packet.active & 0xFFFFu & segment_lanes(packet);
        if (active == 0) continue;
        const float* dir[3] = {packet.dir_x, packet.dir_y, packet.dir_z};
        const float* org[3] = {packet.org_x, packet.org_y, packet.org_z};
        if (!any) {
            const int lead = __builtin_ctz(active);
            main_axis_of_beam = main_of(packet, active);
            first_origin = Float3{org[0][lead], org[1][lead], org[2][lead]};
            for (int k = 0; k < 3; ++k) lead_org[k] = Lanes(org[k][lead]);
            any = true;
        }
        rays_added += std::uint32_t(__builtin_popcount(active));
        std::uint32_t neg[3] = {0, 0, 0}, zeros = 0, same_bits = 0;
        // Four lanes at a time; groups with every lane on skip the masking (the same values).
        auto four_lanes = [&](int base, auto all_on) {
            const LaneMask on = lanes_on((active >> base) & 0xFu);
            auto add = [&](LaneRange& r, const Lanes& v) {
                if constexpr (decltype(all_on)::value)
                    r.add(v);
                else
                    r.add(on, v);
            };
            const Lanes tnear = Lanes::load_unaligned(packet.tnear + base),
                        tfar = Lanes::load_unaligned(packet.tfar + base);
            LaneMask same = on;
            for (int k = 0; k < 3; ++k) {
                const Lanes v = Lanes::load_unaligned(dir[k] + base), o = Lanes::load_unaligned(org[k] + base);
                zeros |= bits_of(v == Lanes(0.0f)) << base;
                neg[k] |= std::uint32_t(_mm_movemask_ps(v)) << base;  // sign bits
                add(d[k], v);
                add(s[k], o + v * tnear);
                same = same & (o == lead_org[k]);
            }
            same_bits |= bits_of(same) << base;
            const Lanes mag = xsimd::abs(Lanes::load_unaligned(dir[main_axis_of_beam] + base));
            add(len, (tfar - tnear) * mag);
            add(near, tnear * mag);
            add(far, tfar * mag);
        };
        for (int base = 0; base < 16; base += kLanes) {
            const std::uint32_t four = (active >> base) & 0xFu;
            if (four == 0xFu)
                four_lanes(base, std::true_type{});
            else if (four != 0)  // (no lane on: nothing to add)
                four_lanes(base, std::false_type{});
        }
        zero = zero || (zeros & active) != 0;
        same_origin = same_origin && (same_bits & active) == active;
        for (int k = 0; k < 3; ++k) {
            // One sign per axis: bit 0 some ray negative, bit 1 some positive (both: incoherent).
            const std::uint32_t n = neg[k] & active;
            negative[k] |= n == 0 ? 2u : (n == active ? 1u : 3u);
        }
    }
    if (!any) return;
    Beam b;
    b.empty = false;
    b.rays = rays_added;
    b.main_axis = main_axis_of_beam;
    Interval start[3], dir_range[3];
    for (int k = 0; k < 3; ++k) {
        start[k] = s[k].interval();
        dir_range[k] = d[k].interval();
    }
    b.starts.lower = Float3{start[0].lo, start[1].lo, start[2].lo};
    b.starts.upper = Float3{start[0].hi, start[1].hi, start[2].hi};
    b.length = len.interval();
    b.one_origin = same_origin;
    b.origin = first_origin;
    b.apex_near = near.interval();
    b.apex_far = far.interval();
    b.pad = pad;
    b.coherent = !zero;
    for (int k = 0; k < 3; ++k) {
        if (negative[k] == 3u) b.coherent = false;
        b.sign[k] = negative[k] == 1u ? -1 : 1;
    }
    if (b.coherent) {
        for (int k = 0; k < 3; ++k) {
            const Interval inv = {1.0f / dir_range[k].hi, 1.0f / dir_range[k].lo};  // one sign
            for (int j = 0; j < 3; ++j) b.slope[k][j] = j == k ? Interval{1.0f, 1.0f} : widen(dir_range[j] * inv, 0.0f);
        }
    }
    merge(b);
}

int Beam::main_of(const Packet16& packet, std::uint32_t active) {
    const int i = __builtin_ctz(active);
    return dominant_axis(Float3{packet.dir_x[i], packet.dir_y[i], packet.dir_z[i]});
}

void Beam::merge(const Beam& o) {
    if (o.empty) return;
    if (empty) {
        const float keep_pad = pad;
        *this = o;
        pad = std::max(keep_pad, o.pad);
        return;
    }
    for (int k = 0; k < 3; ++k)
        if (o.sign[k] != sign[k]) coherent = false;
    coherent = coherent && o.coherent;
    starts.extend(o.starts);
    one_origin = one_origin && o.one_origin && o.origin == origin;
    if (coherent) {
        // The other beam measures its lengths along its own main axis: convert them to ours with
        // |dir_main / dir_other_main|, the absolute value of its slope range (one sign, non-zero).
        Interval other_length = o.length, other_near = o.apex_near, other_far = o.apex_far;
        if (o.main_axis != main_axis) {
            const Interval s = o.slope[o.main_axis][main_axis];
            const Interval ratio = s.lo > 0.0f ? s : Interval{-s.hi, -s.lo};
            other_length = widen(o.length * ratio, 0.0f);
            other_near = widen(o.apex_near * ratio, 0.0f);
            other_far = widen(o.apex_far * ratio, 0.0f);
        }
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j) slope[k][j] = hull(slope[k][j], o.slope[k][j]);
        length = hull(length, other_length);
        apex_near = hull(apex_near, other_near);
        apex_far = hull(apex_far, other_far);
    }
    pad = std::max(pad, o.pad);
    rays += o.rays;
}

void Beam::set_scene_scale(const Box& b) {
    float scale = b.diagonal();
    for (int k = 0; k < 3; ++k) scale = std::max({scale, std::fabs(b.lower[k]), std::fabs(b.upper[k])});
    pad = std::ldexp(scale, -20);
}

Interval Beam::plane_range(int k, float p, int j) const {
    const Interval offset = widen({p - starts.upper[k], p - starts.lower[k]}, pad);
    const Interval along = widen(offset * slope[k][j], pad);
    return widen(Interval{starts.lower[j], starts.upper[j]} + along, pad);
}

Interval Beam::plane_t(int k, float p) const {
    // t' = (p - start_k) / (dir_k / |dir_main|) with dir_k / |dir_main| = slope[main][k] * sign[main].
    const Interval offset = widen({p - starts.upper[k], p - starts.lower[k]}, pad);
    const Interval s = slope[main_axis][k];
    const float m = float(sign[main_axis]);
    const Interval per_unit = m > 0 ? Interval{1.0f / s.hi, 1.0f / s.lo} : Interval{-1.0f / s.lo, -1.0f / s.hi};
    return widen(offset * Interval{std::min(per_unit.lo, per_unit.hi), std::max(per_unit.lo, per_unit.hi)}, pad);
}

Beam pinhole_beam(Float3 eye, Float3 base, Float3 du, Float3 dv, float x0, float y0, float x1, float y1) {
    Beam beam;
    for (float y : {y0, y1})
        for (float x : {x0, x1}) beam.add(Ray{eye, 0.0f, base + du * x + dv * y, kInfinity});
    return beam;
}

}  // namespace beamtrace::mlrta
