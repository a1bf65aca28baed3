// DirectionSet: the beam directions Omega_l and the table behind their constant-time lookup.
//
// Directions (section 3.1; the paper subdivides a tetrahedron, any near-uniform construction will
// do): the grid points (i/m, j/m), |i| + |j| <= m, of the equal-area octahedral map of the upper
// hemisphere, in the quadrant u, v >= 0
//     r = u + v,  phi = (pi/2) v / r,  z = 1 - r^2,  (x, y) = r sqrt(2 - r^2) (cos phi, sin phi),
// mirrored into the other quadrants. Equal-area means every grid cell covers the same solid angle,
// so the points are spread evenly. Rim points (r = 1) come in opposite pairs of which one is kept:
// 2 m^2 - 2 m + 1 interior points plus 2 m rim points = 2 m^2 + 1.
//
// Lookup table (Slater's constant-time query, JGT 2002, in spirit: a precomputed map from a cheap
// parameterisation of the hemisphere to the few stored points that can be nearest there). For a
// cell C with centre direction c and angular radius rho (every direction of C within rho of c):
// if p is the point nearest to c at angle alpha, every direction x of C has its nearest point q
// within angle(x, p) <= rho + alpha of x, hence within alpha + 2 rho of c. So the points within
// alpha + 2 rho of c are the only candidates. Cells map to spherical quadrilaterals with great-arc
// edges (within one octant the map is a central projection of a plane), so rho is the largest
// angle from c to a corner; the cell is first grown by 1e-5 in (u, v) to cover rounding of the
// query's own (u, v), and rho gets a further margin of 1e-4 radians.
#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "beamtrace/error.hpp"
#include "vlf/directions/direction_set_impl.hpp"

namespace beamtrace {
namespace {

constexpr int kMaxM = 32;
// Table cells per grid step of the point lattice (per unit of 1/m in u): finer cells mean fewer
// candidates per cell (see candidates_per_lookup()) and a bigger table.
constexpr int kCellsPerStep = 8;
constexpr double kCellGrowth = 1e-5;
constexpr double kAngleMargin = 1e-4;

struct D3 {
    double x, y, z;
};
D3 normalized(D3 a) {
    const double l = std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
    return {a.x / l, a.y / l, a.z / l};
}
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

int m_of(int count) {
    for (int m = 1; m <= kMaxM; ++m)
        if (2 * m * m + 1 == count) return m;
    return 0;
}

// The equal-area octahedral map of grid point (i, j) (|i| + |j| <= m).
D3 lattice_direction(int i, int j, int m) {
    const double a = double(i) / m, b = double(j) / m, r = std::fabs(a) + std::fabs(b);
    if (r == 0.0) return {0.0, 0.0, 1.0};
    const double phi = 1.5707963267948966 * std::fabs(b) / r;
    const double s = r * std::sqrt(2.0 - r * r);
    const double x = i == 0 ? 0.0 : std::copysign(s * std::cos(phi), a);
    const double y = j == 0 ? 0.0 : std::copysign(s * std::sin(phi), b);
    return {x, y, 1.0 - r * r};
}

// The square cell [u0, u1] x [v0, v1] (grown by kCellGrowth) clipped to its octant's side of the
// rim, su * u + sv * v <= 1 + kCellGrowth; returns the corners of the clipped polygon.
int clipped_cell(double u0, double u1, double v0, double v1, double (*out)[2]) {
    u0 -= kCellGrowth;
    v0 -= kCellGrowth;
    u1 += kCellGrowth;
    v1 += kCellGrowth;
    const double su = (u0 + u1) > 0.0 ? 1.0 : -1.0, sv = (v0 + v1) > 0.0 ? 1.0 : -1.0;
    const double in[4][2] = {{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}};
    auto f = [&](const double* p) { return 1.0 + kCellGrowth - (su * p[0] + sv * p[1]); };  // >= 0 inside
    int n = 0;
    for (int k = 0; k < 4; ++k) {
        const double* a = in[k];
        const double* b = in[(k + 1) % 4];
        const double fa = f(a), fb = f(b);
        if (fa >= 0.0) {
            out[n][0] = a[0];
            out[n][1] = a[1];
            ++n;
        }
        if ((fa >= 0.0) != (fb >= 0.0)) {
            const double s = fa / (fa - fb);
            out[n][0] = a[0] + s * (b[0] - a[0]);
            out[n][1] = a[1] + s * (b[1] - a[1]);
            ++n;
        }
    }
    return n;
}

D3 octahedral_point(double u, double v) { return normalized({u, v, std::max(0.0, 1.0 - std::fabs(u) - std::fabs(v))}); }

}  // namespace

bool DirectionSet::valid_count(int count) { return m_of(count) != 0; }

DirectionSet::DirectionSet(int count) {
    const int m = m_of(count);
    if (m == 0) {
        std::string valid;
        for (int k = 1; k <= 6; ++k) valid += std::to_string(2 * k * k + 1) + ", ";
        throw Error("VLF direction count " + std::to_string(count) + " is not 2 m^2 + 1 for m = 1..32 (" + valid +
                    "..., 129, ..., 513, ..., 2049)");
    }
    auto impl = std::make_shared<Impl>();
    impl->m = m;
    impl->count = count;
    // The points, and for the table the rim points' opposites as well (same index).
    std::vector<D3> points;
    std::vector<std::uint16_t> label;
    for (int j = -m; j <= m; ++j)
        for (int i = -m; i <= m; ++i) {
            const int r = std::abs(i) + std::abs(j);
            if (r > m) continue;
            if (r == m && !(j > 0 || (j == 0 && i > 0))) continue;  // the other half of the rim
            const D3 d = lattice_direction(i, j, m);
            const Float3 f{float(d.x), float(d.y), float(d.z)};
            const auto index = std::uint16_t(impl->dirs.size());
            impl->dirs.push_back(f);
            points.push_back({double(f.x), double(f.y), double(f.z)});
            label.push_back(index);
            if (r == m) {
                points.push_back({-double(f.x), -double(f.y), -double(f.z)});
                label.push_back(index);
            }
        }
    if (int(impl->dirs.size()) != count) throw Error("VLF direction set: internal count mismatch");
    for (const Float3& d : impl->dirs) {
        impl->dx.push_back(d.x);
        impl->dy.push_back(d.y);
        impl->dz.push_back(d.z);
    }

    // The lookup table.
    const int T = 2 * kCellsPerStep * m;
    impl->table = T;
    impl->half_table = float(T) * 0.5f;
    std::vector<std::vector<std::uint16_t>> lists(std::size_t(T) * std::size_t(T));
    tbb::parallel_for(tbb::blocked_range<int>(0, T), [&](const tbb::blocked_range<int>& rows) {
        std::vector<std::pair<double, std::uint16_t>> near;
        for (int iv = rows.begin(); iv < rows.end(); ++iv)
            for (int iu = 0; iu < T; ++iu) {
                const double u0 = -1.0 + 2.0 * iu / T, v0 = -1.0 + 2.0 * iv / T;
                double poly[8][2];
                const int n = clipped_cell(u0, u0 + 2.0 / T, v0, v0 + 2.0 / T, poly);
                std::vector<std::uint16_t>& list = lists[std::size_t(iv) * T + iu];
                if (n == 0) {  // wholly beyond the rim: no query lands here
                    list.push_back(0);
                    continue;
                }
                D3 corners[8], sum{0, 0, 0};
                for (int k = 0; k < n; ++k) {
                    corners[k] = octahedral_point(poly[k][0], poly[k][1]);
                    sum = {sum.x + corners[k].x, sum.y + corners[k].y, sum.z + corners[k].z};
                }
                const D3 c = normalized(sum);
                double rho = 0.0;
                for (int k = 0; k < n; ++k) rho = std::max(rho, std::acos(std::min(1.0, dot(c, corners[k]))));
                rho += kAngleMargin;
                double best = -2.0;
                for (const D3& p : points) best = std::max(best, dot(c, p));
                const double alpha = std::acos(std::min(1.0, best));
                const double limit = std::cos(std::min(3.14159, alpha + 2.0 * rho));
                near.clear();
                for (std::size_t k = 0; k < points.size(); ++k) {
                    const double d = dot(c, points[k]);
                    if (d >= limit) near.emplace_back(-d, label[k]);
                }
                std::sort(near.begin(), near.end());
                for (const auto& [d, index] : near)
                    if (std::find(list.begin(), list.end(), index) == list.end()) list.push_back(index);
            }
    });
    std::size_t k = 2;
    for (const auto& list : lists) k = std::max(k, (list.size() + 1) / 2 * 2);
    impl->per_cell = int(k);
    impl->candidate_pairs.assign(lists.size() * k / 2, 0);
    for (std::size_t c = 0; c < lists.size(); ++c)
        for (std::size_t i = 0; i < k; ++i)
            impl->candidate_pairs[(c * k + i) / 2] |= std::uint32_t(lists[c][i < lists[c].size() ? i : 0])
                                                      << (16 * (i & 1));
    impl_ = std::move(impl);
}

int DirectionSet::size() const { return impl_->count; }
Float3 DirectionSet::direction(int i) const { return impl_->dirs[std::size_t(i)]; }
DirectionSet::Nearest DirectionSet::nearest(Float3 d) const { return impl_->nearest(d.x, d.y, d.z); }
int DirectionSet::candidates_per_lookup() const { return impl_->per_cell; }
std::size_t DirectionSet::memory_bytes() const {
    return impl_->dirs.size() * (sizeof(Float3) + 3 * sizeof(float)) +
           impl_->candidate_pairs.size() * sizeof(std::uint32_t);
}

}  // namespace beamtrace
