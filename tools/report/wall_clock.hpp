#pragma once
// Wall-clock seconds since a point of std::chrono::steady_clock: how tools time builds and passes.
#include <chrono>

namespace beamtrace::report {

inline double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace beamtrace::report
