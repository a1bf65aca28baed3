#pragma once
// The sorting step of the stream tracer: a stable least-significant-digit radix sort of 32-bit keys
// with their indices (three passes of 11 bits; a pass whose digit all keys share is skipped), in
// linear time, on `parts` threads of the caller's TBB arena (histograms and scatters by part).
#include <cstdint>
#include <span>
#include <vector>

namespace beamtrace::stream {

// Fills `order` with 0 .. keys.size()-1 sorted by key (equal keys keep their input order) and
// sorted_keys[k] with keys[order[k]]. `scratch` is resized as needed (reused across calls).
void sort_by_key(std::span<const std::uint32_t> keys, std::span<std::uint32_t> order,
                 std::span<std::uint32_t> sorted_keys, int parts, std::vector<std::uint64_t>& scratch);

}  // namespace beamtrace::stream
