#pragma once
// Instruction sets the SIMD kernels are compiled for, and the run-time choice among them.
#include <string>

namespace beamtrace {

enum class Isa { scalar = 0, sse42 = 1, avx2 = 2, avx512 = 3 };

// True if this CPU (and OS) can run kernels of that instruction set. scalar is always available.
bool isa_available(Isa isa);
// The widest available instruction set, unless the environment variable BEAMTRACE_ISA names a
// narrower one (scalar, sse42, avx2, avx512) to force it.
Isa best_isa();
const char* isa_name(Isa isa);
// Parses the names above; throws beamtrace::Error for anything else or an unavailable ISA.
Isa parse_isa(const std::string& name);

}  // namespace beamtrace
