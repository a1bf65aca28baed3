#pragma once
// The benchmarks' scene names: "bunny" is ../shared/scenes/bunny00.off (found through the compile
// definition BEAMTRACE_SCENES_DIR), every other name is a procedural scene spec (tools/scenes).
#include <filesystem>
#include <optional>
#include <string>

#ifndef BEAMTRACE_SCENES_DIR
#error "BEAMTRACE_SCENES_DIR must name the folder of the shared scene files"
#endif

namespace beamtrace::bench {

// The scene spec for `name`, or nothing (and `error` saying why) when its file is absent.
inline std::optional<std::string> scene_spec(const std::string& name, std::string& error) {
    if (name != "bunny") return name;
    const std::string path = std::string(BEAMTRACE_SCENES_DIR) + "/bunny00.off";
    if (std::filesystem::exists(path)) return path;
    error = "scene file " + path + " is absent: " + name + " benchmarks skipped";
    return std::nullopt;
}

}  // namespace beamtrace::bench
