#include "mlrta/beam.hpp"

#include <algorithm>
#include <cmath>
#include <span>

namespace beamtrace::mlrta {

namespace {

bool positive(float v) { return !std::signbit(v); }

void extend(Interval& i, float v, bool first) {
    if (first)
        i = {v, v};
    else
        i = {std::min(i.lo, v), std::max(i.hi, v)};
}

}  // namespace

void Beam::add(const Ray& ray) {
    const bool first = empty;
    if (first) {
        for (int k = 0; k < 3; ++k) sign[k] = positive(ray.dir[k]) ? 1 : -1;
        coherent = true;
        main_axis = kdtree::dominant_axis(ray.dir.x, ray.dir.y, ray.dir.z);
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

void Beam::add(const Packet16& packet) {
    const Packet16* one = &packet;
    add(std::span<const Packet16* const>(&one, 1));
}

void Beam::add(std::span<const Packet16* const> packets, kdtree::PacketSetRangesKernel ranges_of) {
    // Per-component ranges of the active rays over every packet (a few operations per ray: this runs
    // for every packet of every tile), then the slopes by interval division: looser than per-ray
    // slopes. Rays that describe no segment are traced by nobody and must not widen (or poison) the
    // beam: they are left out, like inactive lanes. Lengths are measured along the main axis of the
    // first ray (any axis on which every ray has a non-zero component will do; a ray with a zero one
    // makes the beam incoherent).
    kdtree::PacketSetRanges r;
    ranges_of(packets, r);
    if (r.rays == 0) return;
    Beam b;
    b.empty = false;
    b.rays = r.rays;
    b.main_axis = r.main_axis;
    b.starts.lower = Float3{r.start[0].lo, r.start[1].lo, r.start[2].lo};
    b.starts.upper = Float3{r.start[0].hi, r.start[1].hi, r.start[2].hi};
    b.length = r.length;
    b.one_origin = r.same_origin;
    b.origin = r.first_origin;
    b.apex_near = r.near;
    b.apex_far = r.far;
    b.pad = pad;
    b.coherent = !r.zero;
    for (int k = 0; k < 3; ++k) {
        if (r.signs[k] == 3u) b.coherent = false;  // one sign per axis
        b.sign[k] = r.signs[k] == 1u ? -1 : 1;
    }
    if (b.coherent) {
        for (int k = 0; k < 3; ++k) {
            const Interval inv = {1.0f / r.dir[k].hi, 1.0f / r.dir[k].lo};  // one sign
            for (int j = 0; j < 3; ++j) b.slope[k][j] = j == k ? Interval{1.0f, 1.0f} : widen(r.dir[j] * inv, 0.0f);
        }
    }
    merge(b);
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
