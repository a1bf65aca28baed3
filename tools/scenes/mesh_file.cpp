// Mesh files through Assimp, checked at the door: the file first, then whatever Assimp hands back.
#include "scenes/mesh_file.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "beamtrace/error.hpp"

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

// Assimp's messages may end in a newline or carry several lines; keep one line.
std::string one_line(std::string text) {
    for (char& c : text)
        if (c == '\n' || c == '\r') c = ' ';
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return text.empty() ? "unknown error" : text;
}

// Whether Assimp, reading the file as it is (no post-processing, no validation), finds no polygon at
// all: tells "a file without triangles" apart from a broken one when the checked import fails.
bool has_no_polygons(const std::string& path) {
    Assimp::Importer raw;
    const aiScene* ai = raw.ReadFile(path, 0);
    if (ai == nullptr) return false;
    for (unsigned mi = 0; mi < ai->mNumMeshes; ++mi) {
        const aiMesh* mesh = ai->mMeshes[mi];
        for (unsigned fi = 0; mesh != nullptr && mesh->mFaces != nullptr && fi < mesh->mNumFaces; ++fi)
            if (mesh->mFaces[fi].mNumIndices >= 3) return false;
    }
    return true;
}

}  // namespace

SceneSource load_mesh_file(const std::string& path) {
    check_readable(path);
    Assimp::Importer importer;
    // SortByPType splits meshes by primitive type; meshes of points or lines are skipped below.
    const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices |
                           aiProcess_SortByPType | aiProcess_ValidateDataStructure;
    const aiScene* ai = nullptr;
    try {
        ai = importer.ReadFile(path, flags);
        if (ai == nullptr && has_no_polygons(path)) throw Error(path + " contains no triangles");
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error("cannot read " + path + ": Assimp failed: " + one_line(e.what()));
    }
    if (ai == nullptr) throw Error("cannot read " + path + ": " + one_line(importer.GetErrorString()));

    std::vector<Float3> vertices;
    std::vector<std::uint32_t> indices;
    unsigned meshes_used = 0;
    for (unsigned mi = 0; mi < ai->mNumMeshes; ++mi) {
        const aiMesh* mesh = ai->mMeshes[mi];
        if (mesh == nullptr || !(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || mesh->mVertices == nullptr) continue;
        const std::size_t base = vertices.size();
        if (base + mesh->mNumVertices > std::size_t{0xFFFFFFFFu})
            throw Error(path + ": more than 2^32 vertices");
        bool used = false;
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            const aiVector3D& p = mesh->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw Error(path + ": mesh " + std::to_string(mi) + " vertex " + std::to_string(v) +
                            " has a NaN or infinite coordinate");
            vertices.push_back({p.x, p.y, p.z});
        }
        for (unsigned fi = 0; fi < mesh->mNumFaces; ++fi) {
            const aiFace& face = mesh->mFaces[fi];
            if (face.mNumIndices != 3) continue;  // points and lines
            for (unsigned k = 0; k < 3; ++k) {
                if (face.mIndices[k] >= mesh->mNumVertices)
                    throw Error(path + ": mesh " + std::to_string(mi) + " face " + std::to_string(fi) +
                                " refers to vertex " + std::to_string(face.mIndices[k]) + " of " +
                                std::to_string(mesh->mNumVertices));
                indices.push_back(static_cast<std::uint32_t>(base + face.mIndices[k]));
            }
            used = true;
        }
        meshes_used += used ? 1 : 0;
    }
    if (indices.empty()) throw Error(path + " contains no triangles");

    std::optional<Scene> scene;
    try {
        scene.emplace(std::span<const Float3>(vertices), std::span<const std::uint32_t>(indices));
    } catch (const Error& e) {
        throw Error(path + ": " + e.what());
    }
    const std::string name = std::filesystem::path(path).filename().string();
    const Camera camera = frame_from_outside(scene->bounds());
    std::string description = "mesh file " + path + ": " + std::to_string(scene->triangle_count()) +
                              " triangles, " + std::to_string(scene->vertex_count()) + " vertices from " +
                              std::to_string(meshes_used) + (meshes_used == 1 ? " mesh" : " meshes");
    return SceneSource{name, std::move(*scene), camera, std::move(description)};
}

}  // namespace beamtrace::scenes
