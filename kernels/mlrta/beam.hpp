#pragma once
// A beam (MLRTA section 3.3 and condition (3) of section 4.1): a group of rays described only by
//   - one direction sign per axis shared by every ray ("coherent"), and
//   - for any axis-aligned plane, a rectangle containing every ray/plane intersection,
// which is all inverse frustum culling and the entry-point search need. Rays are described from
// their start points (org + tnear * dir), so beams with one origin (a camera, a point light) and with
// many origins (reflections off a flat surface) work the same way.
#include <cstdint>
#include <span>

#include "beamtrace/ray.hpp"
#include "common/interval.hpp"
#include "kdtree/packet/packet_set_ranges.hpp"

namespace beamtrace::mlrta {

struct Beam {
    Box starts;                 // box of the rays' start points
    int sign[3] = {1, 1, 1};    // direction sign per axis (+1 / -1), meaningful when coherent
    Interval slope[3][3] = {};  // slope[k][j]: range of dir_j / dir_k over the rays
    int main_axis = 0;          // the axis along which the beam's parameter t' is measured
    Interval length = {0, 0};   // range of t' at the rays' ends: (tfar - tnear) * |dir_main|
    float pad = 0.0f;           // absolute widening of derived bounds (scene scale * 2^-20)
    bool coherent = false;      // every ray has all three direction components non-zero, one sign per axis
    bool empty = true;          // no ray yet
    std::uint32_t rays = 0;
    // The apex: when every ray has the same origin (bit for bit: a camera, a point light), that
    // origin, and the ranges of tnear * |dir_main| and tfar * |dir_main| (the distances along the
    // main axis from the apex to the rays' starts and ends). Used to cull and to block with
    // triangles (beam_triangles.hpp); the inverse culling only needs `starts`.
    bool one_origin = false;
    Float3 origin;
    Interval apex_near = {0, 0}, apex_far = {0, 0};

    // Adds one ray (a zero direction component or a sign disagreement makes the beam incoherent).
    void add(const Ray& ray);
    // Adds the active rays of a packet (slopes from per-component ranges: a little looser, cheaper).
    void add(const Packet16& packet);
    // Adds the active rays of several packets at once: their ranges reduced once, slopes from the
    // ranges over all of them (looser than merging the packets' beams, and cheaper); `ranges_of` is a
    // kernel table's form of kdtree::packet_set_ranges (the reference when not given).
    void add(std::span<const Packet16* const> packets,
             kdtree::PacketSetRangesKernel ranges_of = kdtree::packet_set_ranges);
    void merge(const Beam& other);
    // Sets the absolute padding from the size of the scene the beam is traced in.
    void set_scene_scale(const Box& scene_bounds);

    // Coordinate j of every ray/plane intersection with the plane x_k = p lies in this interval
    // (intersections behind the start points included: conservative).
    Interval plane_range(int k, float p, int j) const;
    // Range of the parameter t' at which the rays cross the plane x_k = p (t' = 0 at the starts).
    Interval plane_t(int k, float p) const;

};

// A beam from a rectangle of pixels of a pinhole camera without generating its rays: the rays of
// the rectangle have directions base + x * du + y * dv for (x, y) in [x0, x1] x [y0, y1] (pixel
// centres), an affine function, so every ratio dir_j / dir_k over the rectangle lies between its
// values at the four corners. tnear = 0, tfar = +infinity.
Beam pinhole_beam(Float3 eye, Float3 base, Float3 du, Float3 dv, float x0, float y0, float x1, float y1);

}  // namespace beamtrace::mlrta
