#pragma once
// The hashing step of the stream tracer (CRSH's ray hashing, tuned by ray kind; docs/streams.md):
// one 32-bit key per ray, so that a sort puts rays that can be traced together next to each other.
//
//   bit 31 = 1: a ray through a shared point (it starts there, or ends there): bits 20..23 the point,
//               bits 0..19 the octahedral code of its direction (10 bits per coordinate, interleaved;
//               a stream of rays through up to 4 points then sorts in two radix passes, not three)
//   bit 31 = 0: any other ray: bits 0..29 the Morton code of its origin's cell (1024 cells per axis
//               of the scene box); rays with one origin get one key
//   0xFFFFFFFF: a ray that describes no segment (ray.hpp), answered without tracing
#include <cstdint>
#include <span>
#include <vector>

#include "beamtrace/ray.hpp"
#include "simd/dispatch.hpp"
#include "beamtrace/vec.hpp"

namespace beamtrace::stream {

inline constexpr std::uint32_t kPencilBit = 1u << 31;
inline constexpr std::uint32_t kNoSegmentKey = 0xFFFFFFFFu;
inline constexpr int kPointShift = 20;
inline constexpr int kPencilDirectionBits = 10;  // per coordinate

// A point many rays of a stream pass through: their common origin (a camera) or the point they end
// at (a point light: the far end org + tfar * dir lies within `radius` of it).
struct SharedPoint {
    Float3 at;
    bool ends = false;  // rays end here (else: they start here, bit for bit)
};

// The shared points of a stream, found from a sample of its rays: points through which at least
// `fraction` of the sampled rays pass (at most `max_points`). `radius` of end points: 1e-3 of the
// scene box's diagonal.
// `repeated_origins`: sampled rays whose exact origin another sampled ray has, not counting origins
// frequent enough to be shared points. More than none says the stream's origins come in bunches
// spread over the stream (ambient-occlusion rays handed over shuffled, or pass by pass), which the
// sort's origin hashes put back together; diffuse bounces (one ray an origin) have none.
struct SharedPoints {
    std::vector<SharedPoint> points;
    float radius = 0.0f;
    std::size_t repeated_origins = 0;
};
SharedPoints find_shared_points(std::span<const Ray> rays, const Box& scene_box, int sample_rays, float fraction,
                                int max_points);

// The point a ray passes through (index into points), or -1.
int shared_point_of(const Ray& ray, const SharedPoints& shared);

// The octahedral code of a direction: its unit-octahedron projection unfolded onto the square
// [-1, 1]^2, quantised to 2^bits cells per side and interleaved (Morton). Neighbouring directions get
// neighbouring cells everywhere but across the square's edges (the lower half's x = 0 and y = 0,
// where the unfolding mirrors): no seam at the equator and no poles, unlike spherical angles.
std::uint32_t octahedral_code(const Float3& dir, int bits);

// The Morton code of a point's cell among 1024^3 cells of the box (points outside are clamped).
std::uint32_t morton_cell(const Float3& p, const Box& box);

// keys[i] for rays[i], by the kernels of `isa` (every instruction set gives the same keys). keys must
// hold at least rays.size() (else beamtrace::Error).
void make_keys(std::span<const Ray> rays, const Box& scene_box, const SharedPoints& shared,
               std::span<std::uint32_t> keys, Isa isa = Isa::scalar);

// What a call's keys are made from (make_keys fills it once per call).
struct KeyInputs {
    float lower[3] = {0, 0, 0};  // the scene box's lower corner
    float scale[3] = {0, 0, 0};  // 1024 / the box's extent per axis (0 where it is flat)
    const SharedPoint* points = nullptr;
    int point_count = 0;
    float radius = 0.0f;  // SharedPoints::radius
};

// keys[i] for rays[i], i < n. The scalar form is the reference; the SIMD forms
// (ray_keys_impl.hpp) give its keys bit for bit.
using MakeKeysFn = void (*)(const KeyInputs& in, const Ray* rays, std::size_t n, std::uint32_t* keys);
void make_keys_scalar(const KeyInputs& in, const Ray* rays, std::size_t n, std::uint32_t* keys);

struct KeyKernels {
    Isa isa;
    MakeKeysFn make_keys;
};

}  // namespace beamtrace::stream

BEAMTRACE_KERNEL_TABLE(beamtrace::stream::KeyKernels);
