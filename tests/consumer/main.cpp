// Builds a kd-tree over two triangles and checks one hit; exits non-zero on any surprise.
#include <beamtrace/beamtrace.hpp>

#include <cstdio>

int main() {
    const float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 2, 1, 0, 2, 0, 1, 2};
    const std::uint32_t idx[] = {0, 1, 2, 3, 4, 5};
    const beamtrace::Scene scene(v, 6, idx, 2);
    const beamtrace::KdTree tree = beamtrace::KdTree::build(scene);
    const beamtrace::Hit hit = tree.intersect(beamtrace::Ray{{0.2f, 0.2f, -1}, 0.0f, {0, 0, 1}, beamtrace::kInfinity});
    std::printf("hit triangle %u at t=%g\n", hit.triangle, hit.t);
    try {
        const std::uint32_t bad[] = {0, 1, 9};
        beamtrace::Scene broken(v, 6, bad, 1);
        return 1;
    } catch (const beamtrace::Error& e) {
        std::printf("rejected as expected: %s\n", e.what());
    }
    return hit.triangle == 0 && hit.t == 1.0f ? 0 : 1;
}
