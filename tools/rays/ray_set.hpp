#pragma once
// The rays of one benchmark or picture, generated once (never timed) and traced by every engine:
// 4x4 packets, each lane remembering the pixel it belongs to.
#include <cstdint>
#include <string>
#include <vector>

#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"
#include "scenes/camera.hpp"

namespace beamtrace::workload {

// primary: camera rays, closest hit. shadow: rays to point lights (or an area light), occlusion.
// ao: ambient-occlusion rays, occlusion. diffuse: one cosine-weighted bounce ray per primary hit,
// unbounded, closest hit.
enum class Mode { primary, shadow, ao, diffuse };
const char* to_string(Mode mode);
Mode parse_mode(const std::string& text);  // throws beamtrace::Error naming the accepted modes
// Whether the rays of a mode ask for closest hits (primary, diffuse) or occlusion (shadow, ao).
constexpr bool closest_hit(Mode mode) { return mode == Mode::primary || mode == Mode::diffuse; }

// The order rays are handed to the engines in: input (as made: image order for primary and shadow
// rays, a pixel's rays side by side for ao and multi-light shadow rays) or shuffled (the active
// rays in one fixed random permutation, as a wavefront integrator hands rays over).
enum class Order { input, shuffled };
const char* to_string(Order order);
Order parse_order(const std::string& text);  // throws beamtrace::Error naming the accepted orders

inline constexpr std::uint32_t kNoPixel = 0xFFFFFFFFu;

struct RaySet {
    Mode mode = Mode::primary;
    int width = 0, height = 0;
    std::vector<Packet16> packets;
    // Per slot (packet * 16 + lane): the pixel, or kNoPixel if inactive. Empty once released by
    // release_untraced (the bench, which reads no pixel).
    std::vector<std::uint32_t> pixel;
    std::size_t ray_count = 0;         // active lanes over all packets
    // When the packets form an image (primary rays, shadow rays to one light or the area light, in input
    // order): packet (x, y) is packets[y * packets_x + x], each a 4x4 block of pixels. 0 when the packets
    // are in no such order (ao, diffuse, multi-light shadow rays, shuffled or random rays).
    int packets_x = 0, packets_y = 0;

    std::size_t slots() const { return packets.size() * 16; }
    bool active(std::size_t slot) const { return (packets[slot / 16].active >> (slot % 16)) & 1u; }
    Ray ray(std::size_t slot) const { return packets[slot / 16].ray(int(slot % 16)); }
};

// One ray through each pixel centre; each packet is a 4x4 block of pixels (partial blocks at the
// right and bottom edges have inactive lanes).
RaySet make_primary_rays(const scenes::Camera& camera, int width, int height);

// Where a primary ray hit: the point and the geometric normal turned towards the ray's origin.
struct SurfacePoint {
    Float3 position, normal;
};
SurfacePoint surface_point(const Scene& scene, const Ray& ray, const Hit& hit);

// The offset that lifts secondary-ray origins off the surface: 1e-4 of the scene diagonal.
float surface_offset(const Scene& scene);

// One shadow ray per primary hit, from the hit point (lifted off the surface towards the light) to
// the light, ending just before it: tfar = 1 - 1e-4 with the direction light - origin. Packet p and
// lane i hold the shadow ray of primary packet p, lane i (inactive where the primary ray missed).
RaySet make_shadow_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& primary_hits, Float3 light);

// The scene's upper box, where generated lights go: with a = the coordinate axis nearest to `up`
// (largest |component|; y before z before x on ties) and e_k the extent of the scene's box along
// axis k, the top quarter of the box along a (the bottom quarter if up points along -a), every side
// then moved inwards by 5% of e_k. Along a it spans [top - 0.20 e_a, top - 0.05 e_a]; across, the
// box shrunk by 5% of its extent on each side. So lights hang inside a closed room, below its
// ceiling and away from its walls (room: x 0.6..11.4, y 2.56..3.04, z 0.45..8.55).
struct UpperBox {
    Box box;
    int up_axis = 1;       // a
    float up_sign = 1.0f;  // +1: up is +a, -1: up is -a
    Float3 up() const;     // the unit vector of up_axis, times up_sign
};
// up: the camera's `up` (its basis' up if that is zero). Throws beamtrace::Error for an empty box.
UpperBox upper_box(const Box& bounds, Float3 up);

// count point lights spread over the upper box: light i (0-based) at the Halton point i + 1 in bases
// 2, 3 and 5, the first two across (the two other axes, in x, y, z order), the third along up:
// lower + (h2(i+1), h3(i+1), h5(i+1)) * extent on those axes. Deterministic; count in [1, 4096].
std::vector<Float3> spread_lights(const UpperBox& upper, int count);

// The area light: a square perpendicular to the up axis, centred over the scene (the centre of the
// upper box across), on the upper box's top face (the face farthest along up), of side half the
// smaller of the upper box's two extents across. Point (a, b) of the light, a, b in [0, 1), is
// corner + a * edge_u + b * edge_v (edge_u along the first axis across, edge_v along the second).
struct AreaLight {
    Float3 center, edge_u, edge_v;
    float side = 0.0f;
    Float3 point(float a, float b) const { return center + edge_u * (a - 0.5f) + edge_v * (b - 0.5f); }
};
AreaLight area_light(const UpperBox& upper);

// Shadow rays to several point lights: for each primary hit (in slot order) one ray per light, in
// the lights' order, in consecutive lanes (a pixel's rays fill whole packets when there are 16k of
// them, as ao rays do); each ray made as by make_shadow_rays (lifted towards its light, tfar = 1 - 1e-4).
// The packets form no image (packets_x = 0).
RaySet make_shadow_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& primary_hits,
                        const std::vector<Float3>& lights);

// One shadow ray per primary hit to a point of the area light, random and deterministic per pixel,
// made as by make_shadow_rays (ending just before that point); same slots and packets as the primary
// rays (an image when they are one).
RaySet make_area_shadow_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& primary_hits,
                             const AreaLight& light);

// One diffuse bounce ray per primary hit (Mode::diffuse): cosine weighted over the hemisphere of the
// geometric normal turned towards the viewer, random and deterministic per pixel, from the hit point
// lifted off the surface along that normal by surface_offset(); tnear 0, tfar +infinity, answered as
// closest hit. The rays fill packets in slot order (packets_x = 0).
RaySet make_diffuse_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& primary_hits);

// The same rays in another order. input: a copy. shuffled: the active rays in a fixed random
// permutation (Fisher-Yates driven by SplitMix64 from seed kShuffleSeed; it depends only on the
// number of active rays), repacked 16 to a packet in that order (the last one partial), each slot
// keeping its ray's pixel; packets_x = packets_y = 0. Deterministic.
inline constexpr std::uint64_t kShuffleSeed = 15;
RaySet reorder(const RaySet& rays, Order order);

// ao_rays occlusion rays per primary hit over the hemisphere of the geometric normal (cosine
// weighted, stratified, deterministic per pixel), of length 10% of the scene diagonal. The rays of
// one pixel fill consecutive lanes (16 per pixel make one packet).
// With AoDirections::psf each of those directions is replaced by the nearest direction of VLF-RT's
// direction set (either way along its line) that lies inside the normal's hemisphere (redrawn if the
// nearest lies below it), so every AO ray runs exactly along one PSF's beams (the paper's section 7).
struct AoDirections {
    enum class Source { random, psf } source = Source::random;
    int psf_directions = 513;  // l of the direction set for Source::psf
};
AoDirections::Source parse_ao_directions(const std::string& text);  // "random" | "psf"
RaySet make_ao_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& primary_hits, int ao_rays,
                    const AoDirections& directions = {});

// count rays with origins spread over the box grown by 20% on every side and uniformly random
// directions, packed 16 to a packet (incoherent); deterministic for a seed.
RaySet make_random_rays(const Box& box, std::size_t count, unsigned seed, Mode mode = Mode::primary);

// The default point light: halfway between the camera and the centre of the scene's box.
Float3 default_light(const scenes::Camera& camera, const Box& bounds);

}  // namespace beamtrace::workload
