// The Assimp part of the mesh file loader: the file through Assimp's importers and post-processing,
// then every index and coordinate it hands back checked.
#include "scenes/assimp_import.hpp"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cmath>
#include <exception>
#include <string>

#include "beamtrace/error.hpp"

namespace beamtrace::scenes {

namespace {

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

MeshArrays import_with_assimp(const std::string& path) {
    Assimp::Importer importer;
    // Keep the file's meshes apart (PreTransformVertices would join meshes of one material): each is
    // an object of SceneSource::object_of_triangle. The geometry is the same either way.
    importer.SetPropertyBool(AI_CONFIG_PP_PTV_KEEP_HIERARCHY, true);
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

    MeshArrays out;
    out.meshes = 0;
    std::vector<Float3>& vertices = out.vertices;
    std::vector<std::uint32_t>& indices = out.indices;
    for (unsigned mi = 0; mi < ai->mNumMeshes; ++mi) {
        const aiMesh* mesh = ai->mMeshes[mi];
        if (mesh == nullptr || !(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || mesh->mVertices == nullptr)
            continue;
        const std::size_t base = vertices.size();
        if (base + mesh->mNumVertices > std::size_t{0xFFFFFFFFu}) throw Error(path + ": more than 2^32 vertices");
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
            out.mesh_of_triangle.push_back(out.meshes);
            used = true;
        }
        out.meshes += used ? 1 : 0;
    }
    if (indices.empty()) throw Error(path + " contains no triangles");
    if (out.meshes <= 1) out.mesh_of_triangle.clear();
    return out;
}

}  // namespace beamtrace::scenes
