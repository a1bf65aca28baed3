#pragma once
// Ray sets of the CRSH tests besides test_scenes.hpp's random and axis rays: the kinds the method is
// made for (camera rays from one point, shadow rays ending at one light, short AO-like segments), and
// the comparison with brute force, answer by answer.
#include <cstdint>
#include <random>
#include <vector>

#include "beamtrace/crsh.hpp"
#include "beamtrace/kdtree.hpp"

namespace beamtrace::test {

// n rays from one point inside the box's neighbourhood towards random points of the box.
inline std::vector<Ray> camera_rays(const Box& box, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const Float3 e = box.extent();
    const Float3 eye = box.lower + Float3{0.5f * e.x, 0.5f * e.y, -0.3f * e.z};
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        const Float3 target = box.lower + Float3{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z};
        rays.push_back(Ray{eye, 0.0f, target - eye, kInfinity});
    }
    return rays;
}

// Shadow rays: from random points of the box to one light, direction light - origin, [1e-4, 1 - 1e-4].
inline std::vector<Ray> shadow_rays(const Box& box, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const Float3 e = box.extent();
    const Float3 light = box.lower + Float3{0.3f * e.x, 1.1f * e.y, 0.6f * e.z};
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        const Float3 o = box.lower + Float3{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z};
        rays.push_back(Ray{o, 1e-4f, light - o, 1.0f - 1e-4f});
    }
    return rays;
}

// Groups of 8 short segments from one point each, in random directions (ambient occlusion).
inline std::vector<Ray> ao_rays(const Box& box, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), d(-1.0f, 1.0f);
    const Float3 e = box.extent();
    const float length = 0.1f * box.diagonal();
    std::vector<Ray> rays;
    Float3 o;
    for (int i = 0; i < n; ++i) {
        if (i % 8 == 0) o = box.lower + Float3{u(rng) * e.x, u(rng) * e.y, u(rng) * e.z};
        Float3 dir;
        do dir = Float3{d(rng), d(rng), d(rng)};
        while (dot(dir, dir) < 1e-3f || dot(dir, dir) > 1.0f);
        rays.push_back(Ray{o, 0.0f, normalize(dir), length});
    }
    return rays;
}

}  // namespace beamtrace::test
