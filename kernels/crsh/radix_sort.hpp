#pragma once
// The sort of CRSH's (key, ray index) pairs by the library's radix sort (common/radix_sort.hpp:
// least significant digit first, digits of up to 11 bits, stable, a pass whose digit is the same for
// every key skipped): the CPU stand-in for the paper's CUB radix sort; its chunk compression is not needed on
// a CPU (docs/crsh.md).
#include <cstdint>
#include <vector>

namespace beamtrace::crsh {

// Sorts keys ascending, values alongside (equal keys keep their order). Both the same size.
void radix_sort(std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& values);

}  // namespace beamtrace::crsh
