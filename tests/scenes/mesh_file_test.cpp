// Mesh files through Assimp: tiny files of every common format written to a temporary folder, the
// shared scanned meshes, and every way a file can be wrong.
#include "scenes/mesh_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/error.hpp"
#include "scenes/scene_source.hpp"

namespace beamtrace::scenes {
namespace {

namespace fs = std::filesystem;

class MeshFile : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() / ("beamtrace_scenes_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(dir_, ec);
    }

    std::string write(const std::string& name, const std::string& bytes) {
        const fs::path path = dir_ / name;
        std::ofstream(path, std::ios::binary) << bytes;
        return path.string();
    }

    // The beamtrace::Error message of loading `path` through load_scene; fails if nothing is thrown.
    static std::string load_error(const std::string& path) {
        try {
            load_scene(path);
        } catch (const Error& e) {
            return e.what();
        }
        ADD_FAILURE() << path << " loaded without error";
        return "";
    }

    fs::path dir_;
};

constexpr const char* kQuadCorners = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";

TEST_F(MeshFile, ObjCubeOfQuadsIsTriangulatedLinesAndPointsDropped) {
    const std::string path = write("cube.obj",
                                   "# a unit cube of quads, plus a line and a point that must be ignored\n"
                                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                   "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"
                                   "l 1 7\np 3\n");
    const SceneSource s = load_scene(path);
    EXPECT_EQ(s.name, "cube.obj");
    EXPECT_EQ(s.scene.triangle_count(), 12u);
    EXPECT_EQ(s.scene.vertex_count(), 8u);  // identical vertices joined
    EXPECT_EQ(s.scene.bounds().lower, (Float3{0, 0, 0}));
    EXPECT_EQ(s.scene.bounds().upper, (Float3{1, 1, 1}));
    EXPECT_EQ(s.camera.at, (Float3{0.5f, 0.5f, 0.5f}));
    EXPECT_GT(length(s.camera.eye - s.camera.at), 0.5f * std::sqrt(3.0f));
    EXPECT_NE(s.description.find("12 triangles"), std::string::npos) << s.description;
}

TEST_F(MeshFile, AsciiPly) {
    const std::string path = write("quad.ply", std::string("ply\nformat ascii 1.0\nelement vertex 4\n"
                                                           "property float x\nproperty float y\nproperty float z\n"
                                                           "element face 2\nproperty list uchar int vertex_indices\n"
                                                           "end_header\n") +
                                                   kQuadCorners + "3 0 1 2\n3 0 2 3\n");
    const SceneSource s = load_mesh_file(path);
    EXPECT_EQ(s.scene.triangle_count(), 2u);
    EXPECT_EQ(s.scene.bounds().upper, (Float3{1, 1, 0}));
}

TEST_F(MeshFile, OffWithAPolygon) {
    const std::string path = write("quad.off", std::string("OFF\n4 1 0\n") + kQuadCorners + "4 0 1 2 3\n");
    const SceneSource s = load_scene(path);
    EXPECT_EQ(s.scene.triangle_count(), 2u);
    EXPECT_EQ(s.name, "quad.off");
}

TEST_F(MeshFile, AsciiAndBinaryStl) {
    const std::string ascii =
        write("two.stl",
              "solid two\n"
              " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n"
              "  endloop\n endfacet\n"
              " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 1 0\n   vertex 0 1 0\n"
              "  endloop\n endfacet\n"
              "endsolid two\n");
    const SceneSource a = load_scene(ascii);
    EXPECT_EQ(a.scene.triangle_count(), 2u);
    EXPECT_EQ(a.scene.vertex_count(), 4u);

    // Binary: 80-byte header, triangle count, then per triangle a normal, 3 corners, 2 spare bytes.
    std::string bytes(80, 'b');
    const std::uint32_t count = 3;
    bytes.append(reinterpret_cast<const char*>(&count), 4);
    for (std::uint32_t t = 0; t < count; ++t) {
        const float data[12] = {0, 0, 1, float(t), 0, 0, float(t) + 1, 0, 0, float(t), 1, 2};
        bytes.append(reinterpret_cast<const char*>(data), sizeof data);
        bytes.append(2, '\0');
    }
    const SceneSource b = load_scene(write("three.stl", bytes));
    EXPECT_EQ(b.scene.triangle_count(), 3u);
    EXPECT_EQ(b.scene.bounds().upper, (Float3{3, 1, 2}));
}

std::string base64(const std::vector<std::uint8_t>& in) {
    static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < in.size(); i += 3) {
        const std::uint32_t n = (std::uint32_t{in[i]} << 16) | (i + 1 < in.size() ? std::uint32_t{in[i + 1]} << 8 : 0) |
                                (i + 2 < in.size() ? in[i + 2] : 0);
        out += alphabet[(n >> 18) & 63];
        out += alphabet[(n >> 12) & 63];
        out += i + 1 < in.size() ? alphabet[(n >> 6) & 63] : '=';
        out += i + 2 < in.size() ? alphabet[n & 63] : '=';
    }
    return out;
}

TEST_F(MeshFile, GltfWithANodeTransform) {
    // One triangle in an embedded buffer, under a node moved by +10 in x (PreTransformVertices).
    const float corners[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::uint16_t indices[3] = {0, 1, 2};
    std::vector<std::uint8_t> buffer(42);
    std::memcpy(buffer.data(), corners, 36);
    std::memcpy(buffer.data() + 36, indices, 6);
    const std::string json =
        R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)"
        R"("nodes":[{"mesh":0,"translation":[10,0,0]}],)"
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
        R"("buffers":[{"byteLength":42,"uri":"data:application/octet-stream;base64,)" +
        base64(buffer) +
        R"("}],)"
        R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],)"
        R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},)"
        R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";
    const SceneSource s = load_scene(write("triangle.gltf", json));
    EXPECT_EQ(s.scene.triangle_count(), 1u);
    EXPECT_EQ(s.scene.bounds().lower, (Float3{10, 0, 0}));
    EXPECT_EQ(s.scene.bounds().upper, (Float3{11, 1, 0}));
}

TEST_F(MeshFile, MissingFileAndDirectory) {
    const std::string missing = (dir_ / "nothing.obj").string();
    EXPECT_NE(load_error(missing).find("cannot open " + missing + ": no such file"), std::string::npos);
    const std::string m = load_error(dir_.string());
    EXPECT_NE(m.find("cannot open " + dir_.string() + ": it is a directory"), std::string::npos) << m;
}

TEST_F(MeshFile, UnreadableFile) {
    if (::geteuid() == 0) GTEST_SKIP() << "running as root: file permissions do not stop reading";
    const std::string path = write("locked.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    fs::permissions(path, fs::perms::none);
    const std::string m = load_error(path);
    EXPECT_NE(m.find("cannot open " + path + ": Permission denied"), std::string::npos) << m;
}

TEST_F(MeshFile, EmptyFile) {
    const std::string path = write("empty.obj", "");
    const std::string m = load_error(path);
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("the file is empty"), std::string::npos) << m;
}

TEST_F(MeshFile, FileWithoutTriangles) {
    for (const auto& [name, text] :
         {std::pair<std::string, std::string>{"lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n"},
          {"points.obj", "v 0 0 0\nv 1 0 0\np 1 2\n"},
          {"vertices.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"},
          {"lines.ply",
           "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
           "property float y\nproperty float z\nelement edge 1\n"
           "property int vertex1\nproperty int vertex2\nend_header\n"
           "0 0 0\n1 0 0\n0 1\n"}}) {
        const std::string path = write(name, text);
        const std::string m = load_error(path);
        EXPECT_EQ(m, path + " contains no triangles") << name;
    }
    // OFF files are read by our own parser, which says the same.
    const std::string off = write("nofaces.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
    EXPECT_EQ(load_error(off), off + " contains no triangles");
    const std::string lines = write("lines.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n1 2\n");
    EXPECT_EQ(load_error(lines), lines + " contains no triangles");
}

TEST_F(MeshFile, NonFiniteCoordinatesAreRejectedNamingTheFile) {
    const std::string path = write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string m = load_error(path);
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("NaN"), std::string::npos) << m;
}

TEST_F(MeshFile, BadIndicesAreRejectedNamingTheFile) {
    const std::string obj = write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    const std::string ply = write("bad.ply",
                                  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                  "property float y\nproperty float z\nelement face 1\n"
                                  "property list uchar int vertex_indices\nend_header\n"
                                  "0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n");
    for (const std::string& path : {obj, ply}) {
        const std::string m = load_error(path);
        EXPECT_NE(m.find("cannot read " + path + ": "), std::string::npos) << m;
        EXPECT_NE(m.find("range"), std::string::npos) << m;  // "index out of range"
    }
}

TEST_F(MeshFile, GarbageIsRejectedWhateverItsExtension) {
    std::mt19937 random(12345);
    std::string garbage(4096, '\0');
    for (char& c : garbage) c = static_cast<char>(random() & 0xFF);
    for (const char* ext : {"bin", "obj", "ply", "off", "stl", "gltf", "glb", "3ds", "fbx", "dae"}) {
        const std::string path = write(std::string("garbage.") + ext, garbage);
        const std::string m = load_error(path);
        EXPECT_NE(m.find(path), std::string::npos) << ext << ": " << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << ext << ": " << m;
    }
}

// OFF variants our parser reads: counts on the keyword line, comments, colours after the
// coordinates and the faces, no keyword at all, CRLF line ends, polygons as fans.
TEST_F(MeshFile, OffVariants) {
    const std::pair<const char*, std::string> files[] = {
        {"same_line.off", "OFF 4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"},
        {"comments.off",
         "# made by hand\nOFF # keyword\n4 1 0 # counts\n0 0 0\n1 0 0\n# a comment line\n1 1 0\n0 1 0\n"
         "4 0 1 2 3 # a quad\n"},
        {"colours.off",
         "COFF\n4 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 9 9 9 9\n"
         "4 0 1 2 3 0.5 0.5 0.5\n"},
        {"no_keyword.off", "4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"},
        {"crlf.off", "OFF\r\n4 1 0\r\n0 0 0\r\n1 0 0\r\n1 1 0\r\n0 1 0\r\n4 0 1 2 3\r\n"},
        {"no_final_newline.off", "OFF\n4 1\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3"},
    };
    for (const auto& [name, text] : files) {
        const SceneSource s = load_scene(write(name, text));
        EXPECT_EQ(s.scene.triangle_count(), 2u) << name;
        EXPECT_EQ(s.scene.bounds().upper, (Float3{1, 1, 0})) << name;
    }
}

// Hostile OFF files: each refused with one line naming the file and the problem (never a crash,
// never a silently different mesh). The last ones have no .off extension: OFF content is
// recognised and never handed to Assimp's OFF reader, which accepts indices out of range.
TEST_F(MeshFile, OffHostileInputIsRejectedNamingTheProblem) {
    const std::string quad = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    const std::pair<std::string, std::string> cases[] = {
        {"OFF\n4 2 0\n0 0 0\n1 0 0\n# a comment long enough to pass the size check\n", "ends after 2 of 4 vertices"},
        {"OFF\n4 2 0\n" + quad + "3 0 1 2\n", "ends after 1 of 2 faces"},
        {"OFF\n4000000000 1 0\n0 0 0\n", "declares 4000000000 vertices"},
        {"OFF\n3 99999999 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "declares 99999999 faces"},
        {"OFF\n99999999999999999999999 1 0\n", "too large"},
        {"OFF\n-3 1 0\n", "negative vertex count"},
        {"OFF\n4 1 0\n" + quad + "3 0 -1 2\n", "negative vertex index"},
        {"OFF\n4 1 0\n" + quad + "3 0 1 4\n", "refers to vertex 4, out of range (4 vertices)"},
        {"OFF\n4 1 0\n" + quad + "3 0 1 99999999999\n", "refers to vertex 99999999999, out of range"},
        {"OFF\n4 1 0\n" + quad + "3 0 1 2.5\n", "is not a whole number"},
        {"OFF\n4 1 0\n" + quad + "4 0 1 2\n", "has 3 of its 4 vertex indices"},
        {"OFF\n4 1 0\n" + quad + "99999999999999999999 0 1 2\n", "too large"},
        // 2^64 - 1 corners (a fuzzer's find: count + 1 wrapped to 0 and the indices were read past
        // the line's end).
        {"OFF\n4 1 0\n" + quad + "18446744073709551615 0 1 2\n", "has 3 of its 18446744073709551615 vertex indices"},
        {"OFF\n4 1 0\n" + quad + "000018446744073709551615 0 1\n", "has 2 of its 18446744073709551615 vertex indices"},
        {"OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", "NaN or infinite"},
        {"OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n", "NaN or infinite"},
        {"OFF\n3 1 0\n0 0 0\n1 1e39 0\n0 1 0\n3 0 1 2\n", "beyond float's range"},
        {"OFF\n3 1 0\n0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n", "'x' is not a number"},
        {"OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", "fewer than 3 coordinates"},
        {"4OFF\n3 1 0\n", "not supported"},
        {"OFF BINARY\n", "binary OFF is not supported"},
        {"OFF\n", "ends before the vertex and face counts"},
        {"OFF\nthree 1 0\n", "is not a whole number"},
        {std::string("\x7f\x01\xfe garbage\x00\x02", 14), "not an OFF file"},
    };
    int i = 0;
    for (const auto& [text, expected] : cases) {
        const std::string path = write("hostile" + std::to_string(i++) + ".off", text);
        const std::string m = load_error(path);
        EXPECT_NE(m.find(path), std::string::npos) << m;
        EXPECT_NE(m.find(expected), std::string::npos) << "expected \"" << expected << "\" in: " << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
    for (const char* name : {"mesh.dat", "mesh", "mesh.stl"}) {
        const std::string path = write(name, "OFF\n4 1 0\n" + quad + "3 0 1 7\n");
        EXPECT_NE(load_error(path).find("refers to vertex 7, out of range"), std::string::npos) << name;
    }
}

// Hostile PLY headers: counts larger than the bytes after the header (ASCII and binary), truncated
// binary data, broken headers. Checked before Assimp sizes anything by them.
TEST_F(MeshFile, PlyHostileHeadersAreRejectedNamingTheProblem) {
    const std::string props = "property float x\nproperty float y\nproperty float z\n";
    const std::string faces = "element face 1\nproperty list uchar int vertex_indices\n";
    const std::pair<std::string, std::string> cases[] = {
        {"ply\nformat ascii 1.0\nelement vertex 4000000000\n" + props + faces + "end_header\n0 0 0\n3 0 0 0\n",
         "declares 4000000000 'vertex' elements"},
        {"ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + props + faces + "end_header\n" +
             std::string(20, '\0'),
         "declares 3 'vertex' elements (at least 12 bytes each) but only 20 bytes follow"},
        {"ply\nformat ascii 1.0\nelement vertex 18446744073709551615\n" + props + "end_header\n",
         "declares 18446744073709551615 'vertex'"},
        {"ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\n" + props + "end_header\n",
         "not a whole number"},
        {"ply\nformat ascii 1.0\nelement vertex -3\n" + props + "end_header\n", "not a whole number"},
        {"ply\nformat ascii 1.0\nelement vertex 3\n" + props, "no end_header"},
        {"ply\nelement vertex 3\n" + props + "end_header\n0 0 0\n1 0 0\n0 1 0\n", "no format line"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty quaternion x\nend_header\n", "known type"},
        {"ply\nformat fancy 1.0\nend_header\n", "unknown format"},
        {"ply\nformat ascii 1.0\nproperty float x\nend_header\n", "property before any element"},
    };
    int i = 0;
    for (const auto& [text, expected] : cases) {
        const std::string path = write("hostile" + std::to_string(i++) + ".ply", text);
        const std::string m = load_error(path);
        EXPECT_NE(m.find(path), std::string::npos) << m;
        EXPECT_NE(m.find(expected), std::string::npos) << "expected \"" << expected << "\" in: " << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
}

// Found by Fuzz.PlyLoader (kept in tests/fuzz/corpus/ply_loader/regression_triangulate_assert.ply): a
// binary PLY whose faces make Assimp's triangulation fail an internal assertion, which aborts the
// process in Debian's build. The import runs in a child process: the abort becomes an error.
TEST_F(MeshFile, AssimpAbortingOnAFileIsAnErrorNotACrash) {
    const std::string header =
        "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
    const char hex[] =
        "00008000003f8000000000000007000000003f800000000000000703000000000000000100000002030000000000"
        "030000000000000000000200000003";
    std::string body;
    for (std::size_t i = 0; hex[i] != '\0'; i += 2) body += char(std::stoi(std::string(hex + i, 2), nullptr, 16));
    const std::string path = write("triangulate_assert.ply", header + body);
    const std::string m = load_error(path);
    EXPECT_NE(m.find("cannot read " + path + ": "), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

// Hostile OBJ files (read by Assimp, checked by its validation and ours): bad indices and NaN text.
// (Assimp skips lines it does not know, so a stray line of garbage inside an OBJ file is ignored;
// a file of garbage is refused, see GarbageIsRejectedWhateverItsExtension.)
TEST_F(MeshFile, ObjHostileInputIsRejectedNamingTheFile) {
    const std::string corners = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    const std::string cases[] = {
        corners + "f 1 2 -9\n",           // relative index before the first vertex
        corners + "f 1 2 99999999999\n",  // huge
        corners + "f 1 2 4\n",            // one past the end
        "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
        "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n",
        corners + "f 1 2\n",  // a line only
    };
    int i = 0;
    for (const std::string& text : cases) {
        const std::string path = write("hostile" + std::to_string(i++) + ".obj", text);
        const std::string m = load_error(path);
        EXPECT_NE(m.find(path), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
}

// The shared scanned meshes (../shared/scenes beside the checkout); skipped when absent.
void expect_shared_mesh(const std::string& file, std::size_t triangles) {
    const fs::path path = fs::path(BEAMTRACE_SCENES_DIR) / file;
    if (!fs::exists(path)) GTEST_SKIP() << path.string() << " is absent (shared scenes not installed)";
    const SceneSource s = load_scene(path.string());
    EXPECT_EQ(s.name, file);
    EXPECT_EQ(s.scene.triangle_count(), triangles);
    const Box b = s.scene.bounds();
    EXPECT_GT(length(s.camera.eye - b.center()), 0.5f * b.diagonal());  // outside the bounding sphere
}

TEST(SharedMeshes, Bunny) { expect_shared_mesh("bunny00.off", 75'408); }
TEST(SharedMeshes, ChineseDragon) { expect_shared_mesh("ChineseDragon-10kv.off", 19'994); }

}  // namespace
}  // namespace beamtrace::scenes
