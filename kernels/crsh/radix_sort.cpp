#include "crsh/radix_sort.hpp"

#include <array>
#include <cstddef>

namespace beamtrace::crsh {

void radix_sort(std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& values) {
    const std::size_t n = keys.size();
    if (n < 2) return;
    constexpr int kDigits = 8;
    // Every digit's histogram in one read of the keys.
    std::vector<std::array<std::size_t, 256>> count(kDigits);
    for (auto& c : count) c.fill(0);
    for (std::uint64_t k : keys)
        for (int d = 0; d < kDigits; ++d) ++count[d][(k >> (8 * d)) & 0xFFu];
    std::vector<std::uint64_t> keys2(n);
    std::vector<std::uint32_t> values2(n);
    for (int d = 0; d < kDigits; ++d) {
        const std::array<std::size_t, 256>& c = count[d];
        if (c[(keys[0] >> (8 * d)) & 0xFFu] == n) continue;  // one value of this digit: nothing moves
        std::array<std::size_t, 256> offset;
        std::size_t sum = 0;
        for (int b = 0; b < 256; ++b) {
            offset[b] = sum;
            sum += c[b];
        }
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t to = offset[(keys[i] >> (8 * d)) & 0xFFu]++;
            keys2[to] = keys[i];
            values2[to] = values[i];
        }
        keys.swap(keys2);
        values.swap(values2);
    }
}

}  // namespace beamtrace::crsh
