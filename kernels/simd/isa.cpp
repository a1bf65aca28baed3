#include "simd/isa.hpp"

#include <array>
#include <cstdlib>

#include <xsimd/xsimd.hpp>

#include "beamtrace/error.hpp"
#include "simd/dispatch.hpp"

namespace beamtrace {

namespace {

// AVX and AVX-512 state must also be enabled by the OS (XCR0), not only reported by CPUID.
unsigned long long xcr0() {
    unsigned int lo = 0, hi = 0;
    __asm__("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
    return (static_cast<unsigned long long>(hi) << 32) | lo;
}

bool os_saves(unsigned long long bits) {
    unsigned int eax = 0, ebx = 0, ecx = 0, edx = 0;
    __asm__("cpuid" : "=a"(eax), "=b"(ebx), "=c"(ecx), "=d"(edx) : "a"(1), "c"(0));
    const bool osxsave = (ecx >> 27) & 1u;
    return osxsave && (xcr0() & bits) == bits;
}

}  // namespace

bool isa_available(Isa isa) {
    // Read once: kernel tables are selected per call (simd::select), and XGETBV is not free.
    static const std::array<bool, 4> available = [] {
        const xsimd::detail::supported_arch cpu = xsimd::available_architectures();
        return std::array<bool, 4>{
            true, bool(cpu.sse4_2), cpu.avx2 && os_saves(0x6),
            cpu.avx512f && cpu.avx512bw && cpu.avx512dq && cpu.avx512cd && cpu.avx2 && os_saves(0xE6)};
    }();
    const int i = static_cast<int>(isa);
    return i >= 0 && i < 4 && available[std::size_t(i)];
}

const char* isa_name(Isa isa) {
    switch (isa) {
        case Isa::scalar:
            return "scalar";
        case Isa::sse42:
            return "sse42";
        case Isa::avx2:
            return "avx2";
        case Isa::avx512:
            return "avx512";
    }
    return "?";
}

Isa parse_isa(const std::string& name) {
    for (Isa isa : {Isa::scalar, Isa::sse42, Isa::avx2, Isa::avx512}) {
        if (name == isa_name(isa)) {
            if (!isa_available(isa)) throw Error("instruction set '" + name + "' is not available on this CPU");
            return isa;
        }
    }
    throw Error("unknown instruction set '" + name + "' (expected scalar, sse42, avx2 or avx512)");
}

void simd::require_available(Isa isa) {
    if (!isa_available(isa))
        throw Error(std::string("instruction set ") + isa_name(isa) + " is not available on this CPU");
}

Isa best_isa() {
    static const Isa best = [] {
        if (const char* forced = std::getenv("BEAMTRACE_ISA"); forced != nullptr && *forced != '\0')
            return parse_isa(forced);
        for (Isa isa : {Isa::avx512, Isa::avx2, Isa::sse42})
            if (isa_available(isa)) return isa;
        return Isa::scalar;
    }();
    return best;
}

}  // namespace beamtrace
