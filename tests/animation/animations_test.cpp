// The procedural animations of `beamtrace bench --animation` (tools/scenes/animations.hpp): what
// moves, how, and the errors for bad specs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "beamtrace/error.hpp"
#include "scenes/animations.hpp"

namespace {

using beamtrace::Error;
using beamtrace::Float3;
using namespace beamtrace::scenes;

const SceneSource& lite_room() {
    static const SceneSource room = load_scene("room-lite");
    return room;
}

void expect_uniform_times(const AnimationSource& a, std::size_t keyframes) {
    ASSERT_EQ(a.scene.keyframe_count(), keyframes);
    for (std::size_t k = 0; k < keyframes; ++k)
        EXPECT_EQ(a.scene.times()[k], float(k) / float(keyframes - 1)) << a.name << " keyframe " << k;
}

std::size_t triangles_of(const SceneSource& s, std::uint32_t object) {
    return std::size_t(std::count(s.object_of_triangle.begin(), s.object_of_triangle.end(), object));
}

TEST(Animations, TheRoomsSmallObjectsAreItsDeskObjectsAndShelves) {
    const auto small = small_objects(lite_room(), lite_room().camera.at);
    EXPECT_EQ(small.size(), 72u);  // 17 desks with 4 objects each, 4 bookshelf boards with their books
    // Nearest the camera's target first.
    const Float3 target = lite_room().camera.at;
    double last = 0;
    for (std::uint32_t o : small) {
        beamtrace::Box box;
        for (std::size_t t = 0; t < lite_room().object_of_triangle.size(); ++t)
            if (lite_room().object_of_triangle[t] == o) {
                const auto& tri = lite_room().scene.triangle(std::uint32_t(t));
                box.extend(tri.v0);
                box.extend(tri.v1);
                box.extend(tri.v2);
            }
        const Float3 d = box.center() - target;
        const double dist = std::sqrt(double(dot(d, d)));
        EXPECT_GE(dist + 1e-6, last);
        last = dist;
    }
}

TEST(Animations, SpinTurnsEightObjectsAboutTheVertical) {
    const AnimationSource a = make_animation("spin", lite_room());
    expect_uniform_times(a, 13);
    const auto small = small_objects(lite_room(), lite_room().camera.at);
    std::size_t expected = 0;
    for (std::size_t o = 0; o < 8; ++o) expected += triangles_of(lite_room(), small[o]);
    EXPECT_EQ(a.scene.moving_count(), expected);
    EXPECT_EQ(a.scene.triangle_count(), lite_room().scene.triangle_count());
    // Keyframe 0 is the room as it stands; every keyframe keeps heights (a turn about the vertical)
    // and a quarter of the way round a moving vertex has moved.
    const auto base = lite_room().scene.vertices();
    const auto first = a.scene.keyframe(0);
    const auto quarter = a.scene.keyframe(3);  // 90 degrees
    std::size_t moved = 0;
    for (std::size_t v = 0; v < base.size(); ++v) {
        EXPECT_EQ(first[v].x, base[v].x);
        EXPECT_EQ(first[v].z, base[v].z);
        EXPECT_NEAR(quarter[v].y, base[v].y, 1e-5f);
        moved += quarter[v].x != base[v].x || quarter[v].z != base[v].z;
    }
    EXPECT_GT(moved, 0u);
    EXPECT_EQ(a.camera(0.5f).eye.x, lite_room().camera.eye.x);  // the camera stands still
}

TEST(Animations, CometThrowsOneObjectAcrossTheScene) {
    const AnimationSource a = make_animation("comet", lite_room());
    expect_uniform_times(a, 2);
    const auto small = small_objects(lite_room(), lite_room().camera.at);
    EXPECT_EQ(a.scene.moving_count(), triangles_of(lite_room(), small.front()));
    // It travels more than half the scene's diagonal.
    std::uint32_t moving = 0;
    while (!a.scene.is_moving(moving)) ++moving;
    const Float3 d = a.scene.triangle_at(moving, 1.0f).v0 - a.scene.triangle_at(moving, 0.0f).v0;
    EXPECT_GT(std::sqrt(dot(d, d)), 0.5f * lite_room().scene.bounds().diagonal());
}

TEST(Animations, PartyAddsDriftingSpheres) {
    const AnimationSource a = make_animation("party:3", lite_room());
    expect_uniform_times(a, 9);
    EXPECT_EQ(a.scene.triangle_count(), lite_room().scene.triangle_count() + 3 * 1280);
    EXPECT_EQ(a.scene.moving_count(), 3u * 1280u);
    // The spheres stay inside the room at every keyframe.
    const beamtrace::Box room = lite_room().scene.bounds();
    for (std::size_t k = 0; k < a.scene.keyframe_count(); ++k)
        for (const Float3& p : a.scene.keyframe(k)) {
            EXPECT_GE(p.x, room.lower.x);
            EXPECT_LE(p.y, room.upper.y);
        }
    EXPECT_EQ(make_animation("party", lite_room()).name, "party:8");
}

TEST(Animations, FlythroughMovesOnlyTheCamera) {
    const AnimationSource a = make_animation("flythrough", lite_room());
    expect_uniform_times(a, 2);
    EXPECT_EQ(a.scene.moving_count(), 0u);
    EXPECT_EQ(a.camera(0.0f).eye.x, lite_room().camera.eye.x);
    const Float3 end = a.camera(1.0f).eye;
    EXPECT_GT(std::fabs(end.x - lite_room().camera.eye.x), 5.0f);  // across the room's 12 m
    EXPECT_EQ(end.y, lite_room().camera.eye.y);
    const beamtrace::Box room = lite_room().scene.bounds();
    EXPECT_TRUE(end.x > room.lower.x && end.x < room.upper.x && end.z > room.lower.z && end.z < room.upper.z);
}

TEST(Animations, BadSpecsAreNamed) {
    const auto message = [](const std::string& spec, const SceneSource& scene) {
        try {
            make_animation(spec, scene);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message("dance", lite_room()).find("'dance' is unknown"), std::string::npos);
    EXPECT_NE(message("party:0", lite_room()).find("1..256"), std::string::npos);
    EXPECT_NE(message("party:x", lite_room()).find("'x'"), std::string::npos);
    EXPECT_NE(message("party:300", lite_room()).find("1..256"), std::string::npos);
    EXPECT_NE(message("spin:2", lite_room()).find("takes no parameter"), std::string::npos);
    const SceneSource random = load_scene("random:1000");
    EXPECT_NE(message("spin", random).find("no small objects"), std::string::npos);
    EXPECT_NE(message("comet", random).find("no small objects"), std::string::npos);
    EXPECT_EQ(make_animation("party:2", random).scene.moving_count(), 2u * 1280u);
}

}  // namespace
