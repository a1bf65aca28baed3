#pragma once
// A triangle scene whose vertices move: fixed indices, K >= 2 keyframe vertex arrays at strictly
// increasing times, positions between keyframes by one linear interpolation (position(), below) that
// every engine and every snapshot uses, so a query at time t on an engine built for motion answers
// exactly as a static engine built on at(t).
//
// Validated once, like Scene (beamtrace::Error naming the problem and the offending index), and
// copied: the caller's arrays may be freed. An immutable, cheaply copyable handle.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "beamtrace/scene.hpp"
#include "beamtrace/vec.hpp"

namespace beamtrace {

class AnimatedScene {
public:
    // times: K >= 2 finite, strictly increasing keyframe times. keyframes: K * vertex_count points,
    // keyframe k's vertices at [k * vertex_count, (k + 1) * vertex_count). indices: 3 per triangle.
    // Throws for: fewer than two keyframes, times not finite or not increasing, a keyframe array whose
    // size is not K * vertex_count, a NaN or infinite coordinate, an index out of range, no triangles.
    AnimatedScene(std::span<const float> times, std::span<const Float3> keyframes, std::size_t vertex_count,
                  std::span<const std::uint32_t> indices);

    std::size_t keyframe_count() const;
    std::size_t vertex_count() const;
    std::size_t triangle_count() const;
    std::span<const float> times() const;
    float start_time() const;
    float end_time() const;
    std::span<const Float3> keyframe(std::size_t k) const;
    std::span<const std::uint32_t> indices() const;

    // Vertex `vertex` at time t: keyframe k's position p and the next one's q, for the segment
    // times[k] <= t < times[k+1] (the last segment is closed; times outside [start, end] clamp),
    // as p + w * (q - p) in float with w = (t - times[k]) / (times[k+1] - times[k]). A vertex that
    // does not move is returned exactly; at a keyframe time the keyframe's own position is.
    Float3 position(std::uint32_t vertex, float t) const;
    Triangle triangle_at(std::uint32_t triangle, float t) const;
    // The scene at time t, built from position(): the same triangle ids.
    Scene at(float t) const;

    // A triangle moves when some corner is not the same (bit for bit) in every keyframe.
    bool is_moving(std::uint32_t triangle) const;
    std::size_t moving_count() const;
    // The scene with every moving triangle collapsed to its first corner (zero area: kept, so ids stay
    // the caller's, but never hit and never in a kd-tree's leaves): what does not move.
    const Scene& static_part() const;
    // A box holding the triangle at every time of [t0, t1] (exact: position() is monotone in t on a
    // segment, so the corners' positions at t0, t1 and at the keyframes between bound it).
    Box swept_bounds(std::uint32_t triangle, float t0, float t1) const;
    // A box holding every triangle at every time.
    const Box& bounds() const;
    std::size_t memory_bytes() const;

private:
    struct Data;
    std::shared_ptr<const Data> data_;
};

}  // namespace beamtrace
