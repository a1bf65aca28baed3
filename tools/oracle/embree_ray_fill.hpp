#pragma once
// Writing an EmbreeSegment into Embree's own ray layouts (RTCRay, and lane i of RTCRay16). For the
// oracle's sources only: it includes Embree's header.
#include <embree3/rtcore.h>

#include "oracle/embree_segment.hpp"

namespace beamtrace::oracle {

inline void fill_ray(RTCRay& out, const EmbreeSegment& s, float time = 0.0f) {
    out.org_x = s.org.x;
    out.org_y = s.org.y;
    out.org_z = s.org.z;
    out.dir_x = s.dir.x;
    out.dir_y = s.dir.y;
    out.dir_z = s.dir.z;
    out.tnear = s.tnear;
    out.tfar = s.tfar;
    out.time = time;
    out.mask = 0xFFFFFFFFu;
    out.id = 0;
    out.flags = 0;
}

template <class Ray16>
void fill_lane(Ray16& out, int i, const EmbreeSegment& s, float time = 0.0f) {
    out.org_x[i] = s.org.x;
    out.org_y[i] = s.org.y;
    out.org_z[i] = s.org.z;
    out.dir_x[i] = s.dir.x;
    out.dir_y[i] = s.dir.y;
    out.dir_z[i] = s.dir.z;
    out.tnear[i] = s.tnear;
    out.tfar[i] = s.tfar;
    out.time[i] = time;
    out.mask[i] = 0xFFFFFFFFu;
    out.id[i] = static_cast<unsigned>(i);
    out.flags[i] = 0;
}

}  // namespace beamtrace::oracle
