// Ray keys of the stream tracer (ray_keys.hpp).
#include "stream/ray_keys.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "beamtrace/error.hpp"
#include "common/morton.hpp"
#include "common/ray_validity.hpp"

namespace beamtrace::stream {

namespace {

std::uint32_t quantise(float x, int cells) {
    const float q = x * float(cells);
    if (!(q > 0.0f)) return 0;                                                  // NaN too
    return q < float(cells - 1) ? std::uint32_t(q) : std::uint32_t(cells - 1);  // never converts a huge float
}

Float3 far_end(const Ray& r) { return r.org + r.dir * r.tfar; }

float distance2(const Float3& a, const Float3& b) {
    const Float3 d = a - b;
    return dot(d, d);
}

}  // namespace

std::uint32_t octahedral_code(const Float3& dir, int bits) {
    const float l = std::fabs(dir.x) + std::fabs(dir.y) + std::fabs(dir.z);
    float u = dir.x / l, v = dir.y / l;
    if (dir.z < 0.0f) {
        const float fu = (1.0f - std::fabs(v)) * (u >= 0.0f ? 1.0f : -1.0f);
        const float fv = (1.0f - std::fabs(u)) * (v >= 0.0f ? 1.0f : -1.0f);
        u = fu;
        v = fv;
    }
    const int cells = 1 << bits;
    return spread_bits_2(quantise(u * 0.5f + 0.5f, cells)) | (spread_bits_2(quantise(v * 0.5f + 0.5f, cells)) << 1);
}

std::uint32_t morton_cell(const Float3& p, const Box& box) {
    const Float3 e = box.extent();
    std::uint32_t code = 0;
    for (int k = 0; k < 3; ++k) {
        const float x = e[k] > 0.0f ? (p[k] - box.lower[k]) / e[k] : 0.0f;
        code |= spread_bits_3(quantise(x, 1024)) << k;
    }
    return code;
}

SharedPoints find_shared_points(std::span<const Ray> rays, const Box& scene_box, int sample_rays, float fraction,
                                int max_points) {
    SharedPoints shared;
    shared.radius = 1e-3f * std::sqrt(dot(scene_box.extent(), scene_box.extent()));
    if (rays.empty() || sample_rays <= 0 || max_points <= 0) return shared;
    const std::size_t n = rays.size(), samples = std::min<std::size_t>(n, std::size_t(sample_rays));
    // Origins counted bit for bit; far ends by cells of the radius (then merged around their mean).
    // Sorted vectors, not maps (4,096 samples: a map's nodes cost about a millisecond a call): each
    // run of equal keys in sample order (stable sorts), so a run's first origin and its ends' sum in
    // sample order are what a map filled in sample order would hold.
    using Origin = std::tuple<float, float, float>;
    using Cell = std::tuple<std::int64_t, std::int64_t, std::int64_t>;
    std::vector<Origin> origins;
    std::vector<std::pair<Cell, Float3>> ends;
    origins.reserve(samples);
    ends.reserve(samples);
    const float cell = 2.0f * shared.radius;
    for (std::size_t s = 0; s < samples; ++s) {
        const Ray& r = rays[s * n / samples];
        if (!describes_segment(r)) continue;
        origins.emplace_back(r.org.x, r.org.y, r.org.z);
        if (std::isfinite(r.tfar) && cell > 0.0f) {
            const Float3 e = far_end(r);
            if (!(std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.z))) continue;
            ends.emplace_back(Cell{std::int64_t(std::floor(e.x / cell)), std::int64_t(std::floor(e.y / cell)),
                                   std::int64_t(std::floor(e.z / cell))},
                              e);
        }
    }
    std::stable_sort(origins.begin(), origins.end());
    std::stable_sort(ends.begin(), ends.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    const int needed = std::max(2, int(std::ceil(double(fraction) * double(samples))));
    std::vector<std::pair<int, SharedPoint>> found;
    for (std::size_t b = 0, e = 0; b < origins.size(); b = e) {
        for (e = b + 1; e < origins.size() && !(origins[b] < origins[e]);) ++e;  // equal keys (+0 == -0 too)
        const int count = int(e - b);
        const Origin& o = origins[b];
        if (count >= needed)
            found.push_back({count, SharedPoint{{std::get<0>(o), std::get<1>(o), std::get<2>(o)}, false}});
        else
            shared.repeated_origins += std::size_t(count - 1);
    }
    for (std::size_t b = 0, e = 0; b < ends.size(); b = e) {
        Float3 sum{0, 0, 0};
        for (e = b; e < ends.size() && ends[e].first == ends[b].first; ++e) sum = sum + ends[e].second;
        const int count = int(e - b);
        if (count >= needed) found.push_back({count, SharedPoint{sum * (1.0f / float(count)), true}});
    }
    std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& f : found) {
        if (int(shared.points.size()) == max_points) break;
        shared.points.push_back(f.second);
    }
    return shared;
}

namespace {

// The first of points[0 .. count) the ray passes through, or -1 (shared_point_of).
int point_of(const Ray& ray, const SharedPoint* points, int count, float r2) {
    const bool finite = std::isfinite(ray.tfar);
    const Float3 end = finite ? far_end(ray) : ray.org;  // computed once for every point
    for (int p = 0; p < count; ++p) {
        const SharedPoint& s = points[p];
        if (!s.ends) {
            if (ray.org.x == s.at.x && ray.org.y == s.at.y && ray.org.z == s.at.z) return p;
        } else if (finite && distance2(end, s.at) <= r2) {
            return p;
        }
    }
    return -1;
}

}  // namespace

int shared_point_of(const Ray& ray, const SharedPoints& shared) {
    return point_of(ray, shared.points.data(), int(shared.points.size()), shared.radius * shared.radius);
}

void make_keys_scalar(const KeyInputs& in, const Ray* rays, std::size_t n, std::uint32_t* keys) {
    const float r2 = in.radius * in.radius;
    for (std::size_t i = 0; i < n; ++i) {
        const Ray& r = rays[i];
        if (!describes_segment(r)) {
            keys[i] = kNoSegmentKey;
            continue;
        }
        const int p = in.point_count > 0 ? point_of(r, in.points, in.point_count, r2) : -1;
        if (p >= 0) {
            keys[i] = kPencilBit | (std::uint32_t(p) << kPointShift) | octahedral_code(r.dir, kPencilDirectionBits);
            continue;
        }
        std::uint32_t code = 0;
        for (int k = 0; k < 3; ++k) {
            const float q = (r.org[k] - in.lower[k]) * in.scale[k];
            code |= spread_bits_3(!(q > 0.0f) ? 0u : q < 1023.0f ? std::uint32_t(q) : 1023u) << k;
        }
        keys[i] = code;
    }
}

void make_keys(std::span<const Ray> rays, const Box& scene_box, const SharedPoints& shared,
               std::span<std::uint32_t> keys, Isa isa) {
    // morton_cell() with the divisions by the extent done once (the same cells but for rounding of
    // the scale, which only moves points between neighbouring cells).
    KeyInputs in;
    const Float3 e = scene_box.extent();
    for (int k = 0; k < 3; ++k) {
        in.lower[k] = scene_box.lower[k];
        in.scale[k] = e[k] > 0.0f ? 1024.0f / e[k] : 0.0f;
    }
    in.points = shared.points.data();
    in.point_count = int(shared.points.size());
    in.radius = shared.radius;
    if (keys.size() < rays.size())
        throw Error("make_keys: " + std::to_string(keys.size()) + " keys for " + std::to_string(rays.size()) + " rays");
    simd::select<KeyKernels>(isa).make_keys(in, rays.data(), rays.size(), keys.data());
}

}  // namespace beamtrace::stream

template <>
const beamtrace::stream::KeyKernels& beamtrace::simd::table<beamtrace::stream::KeyKernels, beamtrace::Isa::scalar>() {
    static constexpr beamtrace::stream::KeyKernels k{beamtrace::Isa::scalar, beamtrace::stream::make_keys_scalar};
    return k;
}
