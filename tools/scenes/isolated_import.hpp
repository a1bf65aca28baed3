#pragma once
// Assimp in a child process. Assimp trusts its input, and this Debian build aborts on failed
// internal assertions for some malformed files (the PLY fuzzer found one in its triangulation):
// a crash is never an acceptable answer to a bad file, so the import runs in a forked child that
// sends the arrays (or its error) back through a pipe. A child that dies becomes an error.
#include <string>

#include "scenes/mesh_arrays.hpp"

namespace beamtrace::scenes {

// What import_with_assimp(path) returns or throws, computed in a child process. Throws
// beamtrace::Error "cannot read PATH: the importer (Assimp) crashed on it (SIGABRT ...)" when the
// child dies, and "... did not finish within 600 s" (the child is killed) when it hangs.
MeshArrays import_in_child_process(const std::string& path);

}  // namespace beamtrace::scenes
