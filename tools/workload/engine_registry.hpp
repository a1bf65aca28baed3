#pragma once
// Constructors of the engines, one per file; make_engine() (engine_registry.cpp) picks by name.
#include <memory>

#include "oracle/embree_native_rays.hpp"
#include "workload/engine.hpp"

namespace beamtrace::workload {

std::unique_ptr<Engine> make_embree_engine(oracle::EmbreeLayout layout);
std::unique_ptr<Engine> make_brute_engine();
std::unique_ptr<Engine> make_kd1_engine();
std::unique_ptr<Engine> make_kd16_engine();
std::unique_ptr<Engine> make_mlrta_engine();
std::unique_ptr<Engine> make_vlf_engine(bool fast);

}  // namespace beamtrace::workload
