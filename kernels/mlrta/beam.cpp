#include "mlrta/beam.hpp"

#include <cmath>

#include "common/ray_validity.hpp"

namespace beamtrace::mlrta {

namespace {

bool positive(float v) { return !std::signbit(v); }

void extend(Interval& i, float v, bool first) {
    if (first) i = {v, v};
    else i = {std::min(i.lo, v), std::max(i.hi, v)};
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
    if (coherent) {
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j) extend(slope[k][j], j == k ? 1.0f : ray.dir[j] / ray.dir[k], first);
        const float scale = std::fabs(ray.dir[main_axis]);
        extend(length, (ray.tfar - ray.tnear) * scale, first);
    }
    empty = false;
    ++rays;
}

void Beam::add(const Packet16& packet) {
    // Per-component ranges of the active rays, then the slopes by interval division: looser than
    // per-ray slopes but a few operations per ray (this runs for every packet of every tile).
    // Rays that describe no segment are traced by nobody and must not widen (or poison) the beam.
    const std::uint32_t active = packet.active & 0xFFFFu & segment_lanes(packet);
    if (active == 0) return;
    const float* dir[3] = {packet.dir_x, packet.dir_y, packet.dir_z};
    const float* org[3] = {packet.org_x, packet.org_y, packet.org_z};
    Interval d[3] = {}, s[3] = {};
    float len_lo = kInfinity, len_hi = -kInfinity;
    bool first = true, has_zero = false;
    int negative[3] = {0, 0, 0};
    const int main_axis_of_packet = main_of(packet, active);
    for (std::uint32_t m = active; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        const float mag = std::fabs(dir[main_axis_of_packet][i]);
        for (int k = 0; k < 3; ++k) {
            const float v = dir[k][i], p = org[k][i] + v * packet.tnear[i];
            has_zero = has_zero || v == 0.0f;
            negative[k] += std::signbit(v) ? 1 : 0;
            d[k] = first ? Interval{v, v} : Interval{std::min(d[k].lo, v), std::max(d[k].hi, v)};
            s[k] = first ? Interval{p, p} : Interval{std::min(s[k].lo, p), std::max(s[k].hi, p)};
        }
        const float len = (packet.tfar[i] - packet.tnear[i]) * mag;
        len_lo = std::min(len_lo, len);
        len_hi = std::max(len_hi, len);
        first = false;
    }
    Beam b;
    b.empty = false;
    b.rays = std::uint32_t(__builtin_popcount(active));
    b.main_axis = main_axis_of_packet;
    b.starts.lower = Float3{s[0].lo, s[1].lo, s[2].lo};
    b.starts.upper = Float3{s[0].hi, s[1].hi, s[2].hi};
    b.length = {len_lo, len_hi};
    b.pad = pad;
    const int n = int(b.rays);
    b.coherent = !has_zero;
    for (int k = 0; k < 3; ++k) {
        if (negative[k] != 0 && negative[k] != n) b.coherent = false;
        b.sign[k] = negative[k] == n ? -1 : 1;
    }
    if (b.coherent) {
        for (int k = 0; k < 3; ++k) {
            const Interval inv = {1.0f / d[k].hi, 1.0f / d[k].lo};  // d[k] has one sign
            for (int j = 0; j < 3; ++j) b.slope[k][j] = j == k ? Interval{1.0f, 1.0f} : widen(d[j] * inv, 0.0f);
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
    if (coherent) {
        // The other beam measures its lengths along its own main axis: convert them to ours with
        // |dir_main / dir_other_main|, the absolute value of its slope range (one sign, non-zero).
        Interval other_length = o.length;
        if (o.main_axis != main_axis) {
            const Interval s = o.slope[o.main_axis][main_axis];
            const Interval ratio = s.lo > 0.0f ? s : Interval{-s.hi, -s.lo};
            other_length = widen(o.length * ratio, 0.0f);
        }
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j) slope[k][j] = hull(slope[k][j], o.slope[k][j]);
        length = hull(length, other_length);
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
