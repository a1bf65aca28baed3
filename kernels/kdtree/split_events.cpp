#include "kdtree/split_events.hpp"

#include <algorithm>
#include <cmath>

#include "common/radix_sort.hpp"

namespace beamtrace::kd {

void sort_events(AxisEvents& events, AxisEvents& scratch) {
    // Below this many events std::sort is faster than six radix passes.
    constexpr std::size_t kRadixMin = 4096;
    if (events.size() < kRadixMin) {
        std::sort(events.begin(), events.end());
        return;
    }
    radix_sort(
        events, scratch, 64,
        [](const SplitEvent& e) { return (std::uint64_t(sortable_bits(e.pos)) << 32) | e.key; },
        1);
}

namespace {

struct D3 {
    double v[3];
};

// Sutherland-Hodgman clipping of a convex polygon against one half-space (keep side*(p[axis]-pos) >= 0).
int clip_polygon(const D3* in, int n, D3* out, int axis, double pos, double side) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const D3& a = in[i];
        const D3& b = in[(i + 1) % n];
        const double da = side * (a.v[axis] - pos), db = side * (b.v[axis] - pos);
        if (da >= 0) out[m++] = a;
        if ((da >= 0) != (db >= 0)) {
            const double s = da / (da - db);
            D3 p;
            for (int k = 0; k < 3; ++k) p.v[k] = a.v[k] + s * (b.v[k] - a.v[k]);
            p.v[axis] = pos;
            out[m++] = p;
        }
    }
    return m;
}

float round_down(double x) {
    float f = float(x);
    if (double(f) > x) f = std::nextafter(f, -INFINITY);
    return f;
}
float round_up(double x) {
    float f = float(x);
    if (double(f) < x) f = std::nextafter(f, INFINITY);
    return f;
}

int triangle_polygon(const Triangle& tri, D3* poly) {
    const Float3* c = &tri.v0;
    for (int i = 0; i < 3; ++i) poly[i] = D3{{c[i].x, c[i].y, c[i].z}};
    return 3;
}

}  // namespace

Box clipped_bounds(const Triangle& tri, const Box& cell, double slack) {
    D3 a[12], b[12];
    int n = triangle_polygon(tri, a);
    for (int axis = 0; axis < 3 && n > 0; ++axis) {
        n = clip_polygon(a, n, b, axis, double(cell.lower[axis]) - slack, +1.0);
        n = clip_polygon(b, n, a, axis, double(cell.upper[axis]) + slack, -1.0);
    }
    Box box;
    if (n == 0) return box;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], a[i].v[k]);
            hi[k] = std::max(hi[k], a[i].v[k]);
        }
    for (int k = 0; k < 3; ++k) {
        box.lower[k] = std::max(round_down(lo[k]), cell.lower[k]);
        box.upper[k] = std::min(round_up(hi[k]), cell.upper[k]);
        if (box.lower[k] > box.upper[k]) {
            // Only the slack reaches the cell: the triangle touches the cell's face. Keep it on that face.
            if (box.lower[k] > cell.upper[k])
                box.lower[k] = box.upper[k] = cell.upper[k];
            else
                box.lower[k] = box.upper[k] = cell.lower[k];
        }
    }
    return box;
}

void append_events(std::uint32_t tri, const Box& b, AxisEvents (&events)[3]) {
    for (int k = 0; k < 3; ++k) {
        if (b.lower[k] == b.upper[k]) {
            events[k].push_back(SplitEvent(b.lower[k], tri, kPlanar));
        } else {
            events[k].push_back(SplitEvent(b.lower[k], tri, kStart));
            events[k].push_back(SplitEvent(b.upper[k], tri, kEnd));
        }
    }
}

double clipped_planar_area(const Triangle& tri, const Box& cell, int axis) {
    D3 a[12], b[12];
    int n = triangle_polygon(tri, a);
    for (int k = 0; k < 3 && n > 0; ++k) {
        if (k == axis) continue;
        n = clip_polygon(a, n, b, k, cell.lower[k], +1.0);
        n = clip_polygon(b, n, a, k, cell.upper[k], -1.0);
    }
    if (n < 3) return 0.0;
    const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
    double twice = 0.0;
    for (int i = 0; i < n; ++i) {
        const D3& p = a[i];
        const D3& q = a[(i + 1) % n];
        twice += p.v[u] * q.v[v] - q.v[u] * p.v[v];
    }
    return std::fabs(twice) * 0.5;
}

}  // namespace beamtrace::kd
