#pragma once
// The pinhole camera of tools, tests and benchmarks, and the parsers of --camera and --light.
#include <string>

#include "beamtrace/ray.hpp"
#include "beamtrace/vec.hpp"

namespace beamtrace::scenes {

struct Camera {
    Float3 eye, at;
    Float3 up{0, 1, 0};
    float fovy_degrees = 60;  // vertical field of view; the horizontal one follows the image aspect

    // Orthonormal view axes: forward (towards at), right and up as seen in the image. When the view
    // direction is parallel to `up` (or up is zero) another up is picked, so any eye != at works.
    struct Basis {
        Float3 forward, right, up;
    };
    Basis basis() const;

    // Ray through the centre of pixel (px, py) of a width x height image; py = 0 is the TOP row.
    // Direction normalised, tnear 0, tfar +inf. Throws beamtrace::Error for eye == at, a field of view
    // outside (0, 180) degrees, or an empty image; pixels outside the image extrapolate the view.
    Ray primary_ray(int px, int py, int width, int height) const;

    // Throws beamtrace::Error naming the problem (non-finite values, eye == at, fov out of range).
    void validate() const;
};

// "EX,EY,EZ,AX,AY,AZ,FOVY". Throws beamtrace::Error naming the bad field: wrong count, not a number,
// eye == at, fov not in (0, 180). `what` starts the message (e.g. "--camera").
Camera parse_camera(const std::string& text, const std::string& what = "camera");

// The camera as parse_camera reads it ("EX,EY,EZ,AX,AY,AZ,FOVY", 9 significant digits: the same floats
// read back).
std::string format_camera(const Camera& camera);

// A camera that looks at the box centre from outside its bounding sphere, from the front-right and a
// little above (a 3/4 view), just far enough that the whole box is in view, with a small margin, for
// images at least as wide as high. Throws beamtrace::Error for an empty or non-finite box.
Camera frame_from_outside(const Box& bounds);

// "X,Y,Z" (for --light), same error style as parse_camera.
Float3 parse_point(const std::string& text, const std::string& what = "point");

}  // namespace beamtrace::scenes
