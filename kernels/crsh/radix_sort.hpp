#pragma once
// The sort of CRSH's (key, ray index) pairs: a least-significant-digit radix sort with 8-bit digits
// (the CPU stand-in for the paper's CUB radix sort; its chunk compression is not needed on a CPU,
// docs/crsh.md). Stable; a pass whose digit is the same for every key is skipped.
#include <cstdint>
#include <vector>

namespace beamtrace::crsh {

// Sorts keys ascending, values alongside (equal keys keep their order). Both the same size.
void radix_sort(std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& values);

}  // namespace beamtrace::crsh
