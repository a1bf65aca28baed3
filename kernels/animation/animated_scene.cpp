// AnimatedScene (beamtrace/animated_scene.hpp): validation, interpolation, snapshots.
#include "beamtrace/animated_scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "beamtrace/error.hpp"

namespace beamtrace {

struct AnimatedScene::Data {
    std::vector<float> times;
    std::vector<Float3> keyframes;  // K x vertex_count
    std::size_t vertex_count = 0;
    std::vector<std::uint32_t> indices;
    std::vector<std::uint8_t> moving;
    std::size_t moving_count = 0;
    Box bounds;
    std::unique_ptr<Scene> static_part;
};

namespace {

bool same_bits(const Float3& a, const Float3& b) { return std::memcmp(&a, &b, sizeof(Float3)) == 0; }

Float3 lerp(const Float3& p, const Float3& q, float w) {
    return Float3{p.x + w * (q.x - p.x), p.y + w * (q.y - p.y), p.z + w * (q.z - p.z)};
}

}  // namespace

AnimatedScene::AnimatedScene(std::span<const float> times, std::span<const Float3> keyframes,
                             std::size_t vertex_count, std::span<const std::uint32_t> indices) {
    const std::size_t k = times.size();
    if (k < 2) throw Error("animated scene: " + std::to_string(k) + " keyframe time(s); at least two are needed");
    for (std::size_t i = 0; i < k; ++i) {
        if (!std::isfinite(times[i]))
            throw Error("animated scene: keyframe time " + std::to_string(i) + " is not finite");
        if (i > 0 && !(times[i] > times[i - 1]))
            throw Error("animated scene: keyframe time " + std::to_string(i) + " (" + std::to_string(times[i]) +
                        ") does not follow time " + std::to_string(i - 1) + " (" + std::to_string(times[i - 1]) +
                        "); times must increase strictly");
    }
    if (vertex_count == 0) throw Error("animated scene: no vertices");
    if (keyframes.size() != k * vertex_count)
        throw Error("animated scene: " + std::to_string(keyframes.size()) + " keyframe vertices, expected " +
                    std::to_string(k) + " keyframes x " + std::to_string(vertex_count) + " vertices");
    if (indices.size() % 3 != 0)
        throw Error("animated scene: index count " + std::to_string(indices.size()) + " is not a multiple of 3");
    if (indices.empty()) throw Error("animated scene: empty scene (no triangles)");
    auto d = std::make_shared<Data>();
    d->times.assign(times.begin(), times.end());
    d->keyframes.assign(keyframes.begin(), keyframes.end());
    d->vertex_count = vertex_count;
    d->indices.assign(indices.begin(), indices.end());
    for (std::size_t i = 0; i < d->keyframes.size(); ++i) {
        const Float3& p = d->keyframes[i];
        for (int a = 0; a < 3; ++a)
            if (!std::isfinite(p[a]))
                throw Error("animated scene: keyframe " + std::to_string(i / vertex_count) + " vertex " +
                            std::to_string(i % vertex_count) + " has a " + (std::isnan(p[a]) ? "NaN" : "infinite") +
                            " coordinate (" + "xyz"[a] + ")");
        d->bounds.extend(p);
    }
    const std::size_t n = d->indices.size() / 3;
    d->moving.assign(n, 0);
    std::vector<Float3> collapsed(d->keyframes.begin(), d->keyframes.begin() + std::ptrdiff_t(vertex_count));
    std::vector<std::uint32_t> static_indices = d->indices;
    for (std::size_t t = 0; t < n; ++t) {
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = d->indices[3 * t + std::size_t(c)];
            if (v >= vertex_count)
                throw Error("animated scene: triangle " + std::to_string(t) + " corner " + std::to_string(c) +
                            " has vertex index " + std::to_string(v) + ", out of range (vertex count " +
                            std::to_string(vertex_count) + ")");
            for (std::size_t f = 1; f < k && !d->moving[t]; ++f)
                if (!same_bits(d->keyframes[f * vertex_count + v], d->keyframes[v])) d->moving[t] = 1;
        }
        if (d->moving[t]) {
            ++d->moving_count;
            static_indices[3 * t + 1] = static_indices[3 * t + 2] = static_indices[3 * t];
        }
    }
    d->static_part = std::make_unique<Scene>(std::span<const Float3>(collapsed), std::span<const std::uint32_t>(static_indices));
    data_ = std::move(d);
}

std::size_t AnimatedScene::keyframe_count() const { return data_->times.size(); }
std::size_t AnimatedScene::vertex_count() const { return data_->vertex_count; }
std::size_t AnimatedScene::triangle_count() const { return data_->indices.size() / 3; }
std::span<const float> AnimatedScene::times() const { return data_->times; }
float AnimatedScene::start_time() const { return data_->times.front(); }
float AnimatedScene::end_time() const { return data_->times.back(); }
std::span<const Float3> AnimatedScene::keyframe(std::size_t k) const {
    if (k >= keyframe_count())
        throw Error("animated scene: keyframe " + std::to_string(k) + " of " + std::to_string(keyframe_count()));
    return std::span<const Float3>(data_->keyframes).subspan(k * data_->vertex_count, data_->vertex_count);
}
std::span<const std::uint32_t> AnimatedScene::indices() const { return data_->indices; }

Float3 AnimatedScene::position(std::uint32_t vertex, float t) const {
    const std::vector<float>& times = data_->times;
    const std::size_t n = data_->vertex_count;
    if (!(t > times.front())) return data_->keyframes[vertex];  // before the start, or NaN: the first keyframe
    if (t >= times.back()) return data_->keyframes[(times.size() - 1) * n + vertex];
    // The segment: the last keyframe at or before t.
    const std::size_t k = std::size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
    const float w = (t - times[k]) / (times[k + 1] - times[k]);
    return lerp(data_->keyframes[k * n + vertex], data_->keyframes[(k + 1) * n + vertex], w);
}

Triangle AnimatedScene::triangle_at(std::uint32_t triangle, float t) const {
    const std::uint32_t* i = &data_->indices[3 * std::size_t(triangle)];
    return Triangle{position(i[0], t), position(i[1], t), position(i[2], t)};
}

Scene AnimatedScene::at(float t) const {
    if (!std::isfinite(t)) throw Error("animated scene: at(t) needs a finite time");
    std::vector<Float3> v(data_->vertex_count);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = position(std::uint32_t(i), t);
    return Scene(std::span<const Float3>(v), std::span<const std::uint32_t>(data_->indices));
}

bool AnimatedScene::is_moving(std::uint32_t triangle) const { return data_->moving[triangle] != 0; }
std::size_t AnimatedScene::moving_count() const { return data_->moving_count; }
const Scene& AnimatedScene::static_part() const { return *data_->static_part; }
const Box& AnimatedScene::bounds() const { return data_->bounds; }

Box AnimatedScene::swept_bounds(std::uint32_t triangle, float t0, float t1) const {
    const std::vector<float>& times = data_->times;
    const std::size_t n = data_->vertex_count;
    const std::uint32_t* idx = &data_->indices[3 * std::size_t(triangle)];
    Box b;
    for (int c = 0; c < 3; ++c) {
        b.extend(position(idx[c], t0));
        b.extend(position(idx[c], t1));
        // Keyframes strictly inside (t0, t1): the keyframe, and the previous segment's end as the
        // interpolation computes it (w = 1 need not land on the keyframe exactly).
        for (std::size_t k = 1; k < times.size(); ++k) {
            if (!(times[k] > t0 && times[k] < t1)) continue;
            const Float3& p = data_->keyframes[(k - 1) * n + idx[c]];
            const Float3& q = data_->keyframes[k * n + idx[c]];
            b.extend(q);
            b.extend(lerp(p, q, 1.0f));
        }
    }
    return b;
}

std::size_t AnimatedScene::memory_bytes() const {
    return data_->times.capacity() * sizeof(float) + data_->keyframes.capacity() * sizeof(Float3) +
           data_->indices.capacity() * sizeof(std::uint32_t) + data_->moving.capacity() +
           data_->static_part->memory_bytes();
}

}  // namespace beamtrace
