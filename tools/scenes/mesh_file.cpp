// Mesh files, checked at the door: the file first; OFF by our own parser, everything else through
// Assimp in a child process, then whatever Assimp hands back.
#include "scenes/mesh_file.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "beamtrace/error.hpp"
#include "scenes/isolated_import.hpp"
#include "scenes/off_file.hpp"
#include "scenes/ply_header.hpp"

namespace beamtrace::scenes {

namespace {

// Throws "cannot open PATH: reason" unless `path` is a regular, readable, non-empty file.
void check_readable(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (ec || !fs::exists(status)) {
        const std::string reason = ec && ec != std::errc::no_such_file_or_directory ? ec.message() : "no such file";
        throw Error("cannot open " + path + ": " + reason);
    }
    if (fs::is_directory(status)) throw Error("cannot open " + path + ": it is a directory, not a mesh file");
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (file == nullptr) throw Error("cannot open " + path + ": " + std::strerror(errno));
    const bool empty = std::fgetc(file) == EOF;
    std::fclose(file);
    if (empty) throw Error("cannot read " + path + ": the file is empty");
}

// The whole file (already known to be readable).
std::string file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (in.bad()) throw Error("cannot read " + path + ": read error");
    return std::move(bytes).str();
}

std::string lowercase_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

SceneSource make_source(const std::string& path, const MeshArrays& mesh) {
    const std::vector<Float3>& vertices = mesh.vertices;
    const std::vector<std::uint32_t>& indices = mesh.indices;
    const unsigned meshes_used = mesh.meshes;
    std::optional<Scene> scene;
    try {
        scene.emplace(std::span<const Float3>(vertices), std::span<const std::uint32_t>(indices));
    } catch (const Error& e) {
        throw Error(path + ": " + e.what());
    }
    const std::string name = std::filesystem::path(path).filename().string();
    const Camera camera = frame_from_outside(scene->bounds());
    std::string description = "mesh file " + path + ": " + std::to_string(scene->triangle_count()) + " triangles, " +
                              std::to_string(scene->vertex_count()) + " vertices from " + std::to_string(meshes_used) +
                              (meshes_used == 1 ? " mesh" : " meshes");
    // One object per mesh of the file (none known for a file of one mesh).
    std::vector<std::uint32_t> objects;
    if (mesh.mesh_of_triangle.size() == scene->triangle_count()) objects = mesh.mesh_of_triangle;
    return SceneSource{name, std::move(*scene), camera, std::move(description), std::move(objects)};
}

}  // namespace

SceneSource load_mesh_file(const std::string& path) {
    check_readable(path);
    // OFF files (by extension or by content) never reach Assimp, whose OFF reader trusts the file;
    // PLY headers are checked before Assimp sizes anything by their counts.
    {
        const std::string bytes = file_bytes(path);
        if (lowercase_extension(path) == ".off" || looks_like_off(bytes)) {
            const MeshArrays mesh = parse_off(bytes, path);
            return make_source(path, mesh);
        }
        if (lowercase_extension(path) == ".ply" || looks_like_ply(bytes)) check_ply_header(bytes, path);
    }
    const MeshArrays mesh = import_in_child_process(path);
    return make_source(path, mesh);
}

}  // namespace beamtrace::scenes
