// load_scene: dispatch on the spec, and one clear error line for every kind of bad spec.
#include "scenes/scene_source.hpp"

#include <gtest/gtest.h>

#include <string>

#include "beamtrace/error.hpp"
#include "scenes/generators.hpp"

namespace beamtrace::scenes {
namespace {

// The message load_scene(spec) throws as beamtrace::Error; fails the test if it does not throw.
std::string load_error(const std::string& spec) {
    try {
        load_scene(spec);
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_EQ(m.find('\n'), std::string::npos) << "more than one line: " << m;
        return m;
    }
    ADD_FAILURE() << "load_scene(\"" << spec << "\") did not throw";
    return "";
}

TEST(LoadScene, DispatchesToGenerators) {
    const SceneSource r = load_scene("random:1000");
    EXPECT_EQ(r.name, "random:1000");
    EXPECT_EQ(r.scene.triangle_count(), 1000u);
    EXPECT_FALSE(r.description.empty());

    const SceneSource t = load_scene("tetra:2");
    EXPECT_EQ(t.name, "tetra:2");
    EXPECT_EQ(t.scene.triangle_count(), 64u);

    const SceneSource f = load_scene("sphereflake:1");
    EXPECT_EQ(f.name, "sphereflake:1");
    EXPECT_EQ(f.scene.triangle_count(), sphereflake(1).scene.triangle_count());

    EXPECT_EQ(load_scene("tetra: 3").scene.triangle_count(), 256u);  // blanks around the number are fine
}

TEST(LoadScene, RoomDefaultsToSeedOne) {
    const SceneSource plain = load_scene("room");
    const SceneSource one = load_scene("room:1");
    EXPECT_EQ(plain.name, "room:1");
    EXPECT_EQ(plain.scene.triangle_count(), one.scene.triangle_count());
    EXPECT_EQ(plain.camera.eye, one.camera.eye);
    EXPECT_EQ(load_scene("room:7").name, "room:7");
}

TEST(LoadScene, UnknownGenerator) {
    const std::string m = load_error("cube:3");
    EXPECT_NE(m.find("unknown generator \"cube\""), std::string::npos) << m;
    EXPECT_NE(m.find("random:N"), std::string::npos) << m;  // and says what is known
    EXPECT_NE(load_error("spheres").find("unknown generator \"spheres\""), std::string::npos);
}

TEST(LoadScene, BadParameters) {
    struct Case {
        const char* spec;
        const char* expected;
    };
    for (const Case& c :
         {Case{"random:0", "triangle count \"0\" must be between 1 and 10000000"},
          Case{"random:-5", "must be between 1 and 10000000"},
          Case{"random:10000001", "must be between 1 and 10000000"},
          Case{"random:99999999999999999999", "must be between 1 and 10000000"},
          Case{"random:abc", "triangle count \"abc\" is not a whole number"},
          Case{"random:1e3", "is not a whole number"}, Case{"random:", "is not a whole number"},
          Case{"random", "random needs a parameter"}, Case{"tetra", "tetra needs a parameter"},
          Case{"tetra:11", "level \"11\" must be between 0 and 10"}, Case{"tetra:-1", "must be between 0 and 10"},
          Case{"tetra:2.5", "not a whole number"}, Case{"sphereflake:6", "level \"6\" must be between 0 and 5"},
          Case{"room:x", "seed \"x\" is not a whole number"}, Case{"room:-1", "must be between 0 and 4294967295"},
          Case{"", "empty scene spec"}}) {
        const std::string m = load_error(c.spec);
        EXPECT_NE(m.find(c.expected), std::string::npos) << c.spec << " -> " << m;
        if (*c.spec) {
            EXPECT_NE(m.find(std::string("scene ") + c.spec), std::string::npos) << "names the spec: " << m;
        }
    }
}

TEST(LoadScene, MissingFile) {
    const std::string m = load_error("/no/such/dir/mesh.obj");
    EXPECT_NE(m.find("cannot open /no/such/dir/mesh.obj: no such file"), std::string::npos) << m;
    EXPECT_NE(load_error("missing.ply").find("cannot open missing.ply"), std::string::npos);
}

TEST(LoadScene, HelpListsEveryForm) {
    const std::string help = scene_spec_help();
    for (const char* form : {"random:N", "tetra:LEVEL", "sphereflake:LEVEL", "room:SEED", "PATH"})
        EXPECT_NE(help.find(form), std::string::npos) << form;
}

}  // namespace
}  // namespace beamtrace::scenes
