#include "crsh/radix_sort.hpp"

#include "common/radix_sort.hpp"

namespace beamtrace::crsh {

void radix_sort(std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>& values) {
    struct Pair {
        std::uint64_t key;
        std::uint32_t value;
    };
    std::vector<Pair> pairs(keys.size()), scratch;
    for (std::size_t i = 0; i < keys.size(); ++i) pairs[i] = {keys[i], values[i]};
    beamtrace::radix_sort(pairs, scratch, 64, [](const Pair& p) { return p.key; }, 1);
    for (std::size_t i = 0; i < keys.size(); ++i) {
        keys[i] = pairs[i].key;
        values[i] = pairs[i].value;
    }
}

}  // namespace beamtrace::crsh
