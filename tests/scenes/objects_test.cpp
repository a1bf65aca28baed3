// SceneSource::object_of_triangle: the objects the generators and the mesh files give (what the
// crsh engine culls by), and MeshBuilder::begin_object.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <unistd.h>

#include "scenes/generators.hpp"
#include "scenes/mesh_builder.hpp"
#include "scenes/scene_source.hpp"

namespace beamtrace::scenes {
namespace {

// Triangles per object, objects numbered 0..n-1 without gaps.
std::vector<std::size_t> object_sizes(const SceneSource& s) {
    EXPECT_EQ(s.object_of_triangle.size(), s.scene.triangle_count()) << s.name;
    std::vector<std::size_t> sizes;
    for (std::uint32_t o : s.object_of_triangle) {
        if (o >= sizes.size()) sizes.resize(o + 1, 0);
        ++sizes[o];
    }
    for (std::size_t n : sizes) EXPECT_GT(n, 0u) << s.name;
    return sizes;
}

TEST(Objects, MeshBuilderNumbersObjectsInTheOrderBegun) {
    MeshBuilder m;
    EXPECT_TRUE(m.object_of_triangle().empty());
    m.add_triangle(Float3{0, 0, 0}, {1, 0, 0}, {0, 1, 0});  // before any object: object 0
    m.begin_object();
    m.begin_object();  // nothing added since the last call: still one object
    m.add_box(Box{{0, 0, 0}, {1, 1, 1}});
    m.begin_object();
    m.add_tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    std::vector<std::uint32_t> want(1, 0u);
    want.insert(want.end(), 12, 1u);
    want.insert(want.end(), 4, 2u);
    EXPECT_EQ(m.object_of_triangle(), want);
    MeshBuilder n;
    n.begin_object();
    n.add_box(Box{{0, 0, 0}, {1, 1, 1}});
    EXPECT_EQ(n.object_of_triangle(), std::vector<std::uint32_t>(12, 0u));
}

TEST(Objects, SphereflakeHasOneObjectPerSphere) {
    const std::vector<std::size_t> sizes = object_sizes(sphereflake(2));
    ASSERT_EQ(sizes.size(), 91u);
    EXPECT_EQ(sizes[0], 1280u);
    for (std::size_t o = 1; o < sizes.size(); ++o) EXPECT_EQ(sizes[o], 320u);
}

TEST(Objects, TetraHasOneObjectPerSixteenTetrahedra) {
    const std::vector<std::size_t> sizes = object_sizes(sierpinski_tetra(4));
    ASSERT_EQ(sizes.size(), 16u);
    for (std::size_t n : sizes) EXPECT_EQ(n, 64u);
    EXPECT_EQ(object_sizes(sierpinski_tetra(1)), std::vector<std::size_t>{16u});  // below level 2: one object
    EXPECT_EQ(object_sizes(sierpinski_tetra(0)), std::vector<std::size_t>{4u});
}

TEST(Objects, RoomLiteHasEveryPieceOfFurnitureAndDeskObject) {
    const SceneSource lite = room_lite(1);
    EXPECT_EQ(lite.name, "room-lite:1");
    EXPECT_LT(lite.scene.triangle_count(), 40'000u);
    EXPECT_GT(lite.scene.triangle_count(), 15'000u);
    const std::vector<std::size_t> sizes = object_sizes(lite);
    // Shell, pillar, blackboard, 6 lights, the bookshelf's sides and 5 boards (with their books),
    // 17 desks with 4 objects each, 16 chairs.
    EXPECT_EQ(sizes.size(), 3u + 6u + 6u + 17u * 5u + 16u);
    EXPECT_EQ(sizes[0], 12u);  // the shell
    // The same furniture in the same places as the full room (only the desk objects are coarser).
    const SceneSource& same = load_scene("room-lite:1");
    EXPECT_EQ(same.scene.triangle_count(), lite.scene.triangle_count());
    EXPECT_EQ(same.object_of_triangle, lite.object_of_triangle);
}

TEST(Objects, MeshFilesHaveOneObjectPerMesh) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("beamtrace_objects_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path two = dir / "two.obj", one = dir / "one.obj";
    std::ofstream(two) << "o first\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n"
                          "o second\nv 5 0 0\nv 6 0 0\nv 5 1 0\nf 5 6 7\n";
    std::ofstream(one) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const SceneSource a = load_scene(two.string()), b = load_scene(one.string());
    fs::remove_all(dir);
    ASSERT_EQ(a.object_of_triangle.size(), 3u);
    EXPECT_EQ(std::set<std::uint32_t>(a.object_of_triangle.begin(), a.object_of_triangle.end()).size(), 2u);
    EXPECT_EQ(a.object_of_triangle[0], a.object_of_triangle[1]);
    EXPECT_NE(a.object_of_triangle[0], a.object_of_triangle[2]);
    EXPECT_TRUE(b.object_of_triangle.empty());  // one mesh: no partition
}

}  // namespace
}  // namespace beamtrace::scenes
