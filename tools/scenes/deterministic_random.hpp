#pragma once
// Random numbers that are the same on every standard library: std::mt19937's output is fixed by the
// C++ standard, while std::uniform_real_distribution's mapping is not, so the mapping is done here.
#include <cstdint>
#include <random>

namespace beamtrace::scenes {

class DeterministicRandom {
public:
    explicit DeterministicRandom(std::uint32_t seed) : engine_(seed) {}

    // Uniform in [0, 1): the top 24 bits of one draw, exactly representable as a float.
    float unit() { return static_cast<float>(engine_() >> 8) * (1.0f / 16777216.0f); }
    // Uniform in [lo, hi).
    float uniform(float lo, float hi) { return lo + (hi - lo) * unit(); }
    // Uniform integer in [0, n), n >= 1 (multiply-shift; the tiny bias is irrelevant here).
    std::uint32_t below(std::uint32_t n) { return static_cast<std::uint32_t>((std::uint64_t{engine_()} * n) >> 32); }

private:
    std::mt19937 engine_;
};

}  // namespace beamtrace::scenes
