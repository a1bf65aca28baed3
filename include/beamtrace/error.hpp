#pragma once
// Errors the library reports. Every problem with caller input (a bad scene, a bad ray batch, a bad
// build setting) is thrown as beamtrace::Error with a message that names the problem and, where there
// is one, the offending index. Kernels themselves never throw: input is validated where it enters.
#include <stdexcept>
#include <string>

namespace beamtrace {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace beamtrace
