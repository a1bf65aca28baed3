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

enum class Mode { primary, shadow, ao };
const char* to_string(Mode mode);
Mode parse_mode(const std::string& text);  // throws beamtrace::Error naming the accepted modes

inline constexpr std::uint32_t kNoPixel = 0xFFFFFFFFu;

struct RaySet {
    Mode mode = Mode::primary;
    int width = 0, height = 0;
    std::vector<Packet16> packets;
    std::vector<std::uint32_t> pixel;  // per slot (packet * 16 + lane): the pixel, or kNoPixel if inactive
    std::size_t ray_count = 0;         // active lanes over all packets
    // When the packets form an image (primary and shadow rays): packet (x, y) is packets[y * packets_x + x],
    // each a 4x4 block of pixels. 0 when the packets are in no such order (ao, random rays).
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
