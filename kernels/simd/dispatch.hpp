#pragma once
// The one dispatch mechanism of the library's SIMD kernels. A kernel table is a struct of function
// pointers (TriangleKernels, kdtree::PacketKernels, vlf::VlfKernels). Each table has one instance per
// instruction set: the scalar one (the references) beside its kernels, the SSE4.2, AVX2 and AVX-512
// ones in kernels/simd/kernels_<isa>.cpp, the only units compiled for those instruction sets (one
// unit per ISA, which instantiates every xsimd template of that ISA, so that no inline function
// compiled for a wider ISA can be picked by the linker for a narrower one). select<Table>(isa) is the
// only way to reach them and checks once that the CPU can run them.
#include "simd/isa.hpp"

namespace beamtrace::simd {

// The instance of a kernel table for one instruction set; defined by explicit specialisation (see
// BEAMTRACE_KERNEL_TABLE below), never instantiated from this declaration.
template <class Table, Isa I>
const Table& table();

// Throws beamtrace::Error naming the instruction set when this CPU (and OS) cannot run it.
void require_available(Isa isa);

// The table of an instruction set (which must be available: throws beamtrace::Error otherwise).
template <class Table>
const Table& select(Isa isa) {
    require_available(isa);
    switch (isa) {
        case Isa::sse42:
            return table<Table, Isa::sse42>();
        case Isa::avx2:
            return table<Table, Isa::avx2>();
        case Isa::avx512:
            return table<Table, Isa::avx512>();
        case Isa::scalar:
            break;
    }
    return table<Table, Isa::scalar>();
}

}  // namespace beamtrace::simd

// Declares the four instances of a kernel table (in the table's header, so that every use sees them).
#define BEAMTRACE_KERNEL_TABLE(Table)                                         \
    template <>                                                               \
    const Table& ::beamtrace::simd::table<Table, ::beamtrace::Isa::scalar>(); \
    template <>                                                               \
    const Table& ::beamtrace::simd::table<Table, ::beamtrace::Isa::sse42>();  \
    template <>                                                               \
    const Table& ::beamtrace::simd::table<Table, ::beamtrace::Isa::avx2>();   \
    template <>                                                               \
    const Table& ::beamtrace::simd::table<Table, ::beamtrace::Isa::avx512>()
