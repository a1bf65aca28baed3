#pragma once
// The same scene and the same rays, scaled and moved: p -> p * scale + offset, computed in double
// and rounded once to float. Directions are scaled too, so a ray's parameter t means the same
// point before and after (and the comparison's t tolerance keeps its meaning at every scale);
// with unit_directions they keep their (unit) length and t scales instead.
#include "beamtrace/ray.hpp"
#include "scenes/scene_source.hpp"
#include "rays/ray_set.hpp"

namespace beamtrace::test {

struct Placement {
    double scale = 1.0;
    double offset[3] = {0.0, 0.0, 0.0};
    bool unit_directions = false;

    Float3 point(Float3 p) const;
    Float3 direction(Float3 d) const;
    Ray ray(const Ray& r) const;
};

// Every vertex placed; the name says how ("tetra:4 x1e-06 +(0,0,0)"), the camera is placed with it.
scenes::SceneSource placed(const scenes::SceneSource& source, const Placement& placement);
// Every lane of every packet placed (inactive lanes too, so they keep sane values).
workload::RaySet placed(const workload::RaySet& rays, const Placement& placement);

}  // namespace beamtrace::test
