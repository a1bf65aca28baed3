// load_scene: a spec names a generator and its parameter, or a mesh file.
#include "scenes/scene_source.hpp"

#include <array>
#include <cctype>
#include <filesystem>
#include <string_view>
#include <system_error>

#include "beamtrace/error.hpp"
#include "scenes/generators.hpp"
#include "scenes/mesh_file.hpp"
#include "scenes/text_fields.hpp"

namespace beamtrace::scenes {

namespace {

constexpr std::array<std::string_view, 5> kGenerators{"random", "tetra", "sphereflake", "room", "room-lite"};

// "name:parameter" where name is a plain word (letters, digits, '_', '-'): the shape of a generator
// spec. Paths have '/', '.' or '\' before any ':' and never match.
bool looks_like_generator(std::string_view spec, std::string_view& name, std::string_view& parameter,
                          bool& has_parameter) {
    const std::size_t colon = spec.find(':');
    name = spec.substr(0, colon);
    has_parameter = colon != std::string_view::npos;
    parameter = has_parameter ? spec.substr(colon + 1) : std::string_view{};
    if (name.empty()) return false;
    for (char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
    return true;
}

bool is_generator(std::string_view name) {
    for (std::string_view g : kGenerators)
        if (g == name) return true;
    return false;
}

}  // namespace

std::string scene_spec_help() {
    using std::to_string;
    std::string help;
    help += "random:N            N small random triangles in the unit cube, N = 1.." + to_string(kMaxRandomTriangles) +
            "\n";
    help += "tetra:LEVEL         Sierpinski tetrahedron, 4^(LEVEL+1) triangles, LEVEL = 0.." +
            to_string(kMaxTetraLevel) + "\n";
    help += "sphereflake:LEVEL   Haines' sphereflake, LEVEL = 0.." + to_string(kMaxSphereflakeLevel) + "\n";
    help += "room | room:SEED    furnished classroom of about 1M triangles (default seed " +
            to_string(kDefaultRoomSeed) + ")\n";
    help += "room-lite[:SEED]    the same room, desk objects " + to_string(kRoomLiteCoarseness) +
            "x coarser per direction (about 19k triangles)\n";
    help += "PATH                a mesh file: OBJ, PLY, OFF, STL, glTF, ... (through Assimp)";
    return help;
}

SceneSource load_scene(const std::string& spec) {
    std::string_view name, parameter;
    bool has_parameter = false;
    if (looks_like_generator(spec, name, parameter, has_parameter) && is_generator(name)) {
        const std::string what = "scene " + spec;
        if (name == "room" || name == "room-lite") {
            const std::uint32_t seed =
                has_parameter ? static_cast<std::uint32_t>(parse_integer(parameter, 0, 0xFFFFFFFFll, what, "seed"))
                              : kDefaultRoomSeed;
            return name == "room" ? room(seed) : room_lite(seed);
        }
        if (!has_parameter)
            throw Error(what + ": " + std::string(name) + " needs a parameter, e.g. " + std::string(name) +
                        (name == "random" ? ":1000" : ":3"));
        if (name == "random")
            return random_triangles(static_cast<std::size_t>(
                parse_integer(parameter, 1, static_cast<std::int64_t>(kMaxRandomTriangles), what, "triangle count")));
        if (name == "tetra")
            return sierpinski_tetra(static_cast<int>(parse_integer(parameter, 0, kMaxTetraLevel, what, "level")));
        return sphereflake(static_cast<int>(parse_integer(parameter, 0, kMaxSphereflakeLevel, what, "level")));
    }
    if (spec.empty()) throw Error("scene: empty scene spec (give a generator such as room, or a mesh file)");
    // A plain word ("foo", "foo:3") that is no file is a mistyped generator rather than a missing file.
    std::error_code ec;
    if (looks_like_generator(spec, name, parameter, has_parameter) && !std::filesystem::exists(spec, ec))
        throw Error("scene " + spec + ": unknown generator \"" + std::string(name) +
                    "\" and no file of that name (generators: random:N, tetra:LEVEL, sphereflake:LEVEL, room[:SEED], "
                    "room-lite[:SEED])");
    return load_mesh_file(spec);
}

}  // namespace beamtrace::scenes
