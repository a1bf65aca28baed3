#include "workload/engine.hpp"

#include <chrono>

namespace beamtrace::workload {

double Engine::timed_pass(const RaySet& rays, EngineAnswers& answers, int threads, int) {
    const auto start = std::chrono::steady_clock::now();
    if (rays.mode == Mode::primary) intersect(rays, answers.hits, threads);
    else occluded(rays, answers.occluded, threads);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace beamtrace::workload
