// libFuzzer target: the mesh file loader (scenes::load_mesh_file, exactly what --scene FILE runs)
// on hostile bytes written to a file whose extension is FUZZ_EXTENSION (".off", ".obj", ".ply";
// one executable each). A rejection must be one beamtrace::Error line naming the file; anything
// else -- another exception, a crash, a sanitizer or out-of-memory report -- is a finding. A file
// that loads must give a consistent scene.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "beamtrace/error.hpp"
#include "scenes/mesh_file.hpp"

#ifndef FUZZ_EXTENSION
#error "FUZZ_EXTENSION must name the file extension, e.g. \".off\""
#endif

namespace {

const std::string& input_path() {
    static const std::string path = [] {
        const std::filesystem::path dir =
            std::filesystem::temp_directory_path() / ("beamtrace_fuzz_" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir);
        return (dir / ("input" FUZZ_EXTENSION)).string();
    }();
    return path;
}

void check(bool ok) {
    if (!ok) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string& path = input_path();
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) return 0;
    if (size > 0) std::fwrite(data, 1, size, f);
    std::fclose(f);
    try {
        const beamtrace::scenes::SceneSource s = beamtrace::scenes::load_mesh_file(path);
        check(s.scene.triangle_count() > 0);
        const beamtrace::Box& b = s.scene.bounds();
        for (int k = 0; k < 3; ++k) check(std::isfinite(b.lower[k]) && std::isfinite(b.upper[k]));
    } catch (const beamtrace::Error& e) {
        const std::string what = e.what();
        check(what.find(path) != std::string::npos);  // names the file
        check(what.find('\n') == std::string::npos);  // one line
    }
    return 0;
}
