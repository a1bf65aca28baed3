#include "beamtrace/ray.hpp"

namespace beamtrace {

Ray reversed(const Ray& r) {
    Ray out;
    out.org = r.org + r.dir * r.tfar;
    out.dir = r.dir * -1.0f;
    out.tnear = 0.0f;
    out.tfar = r.tfar - r.tnear;
    return out;
}

}  // namespace beamtrace
