#include "support/differential.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace beamtrace::test {

std::string scene_path(const std::string& spec, bool shared_file) {
    return shared_file ? (std::filesystem::path(BEAMTRACE_SCENES_DIR) / spec).string() : spec;
}

std::vector<std::pair<std::string, scenes::Camera>> cameras_for(const scenes::SceneSource& s) {
    const Box& b = s.scene.bounds();
    const Float3 c = b.center(), e = b.extent();
    std::vector<std::pair<std::string, scenes::Camera>> cams;
    cams.emplace_back("default", s.camera);
    scenes::Camera inside;
    inside.eye = c + Float3{0.01f * e.x, 0.013f * e.y, 0.017f * e.z};
    inside.at = inside.eye + Float3{1.0f, -0.2f, 0.4f};
    inside.fovy_degrees = 90.0f;
    cams.emplace_back("inside", inside);
    scenes::Camera grazing;
    grazing.eye = Float3{b.lower.x + 0.05f * e.x, b.lower.y + 1e-4f * e.y, b.lower.z + 0.05f * e.z};
    grazing.at = grazing.eye + Float3{e.x, 0.0f, e.z};
    grazing.fovy_degrees = 40.0f;
    cams.emplace_back("grazing", grazing);
    scenes::Camera on_plane;
    on_plane.eye = Float3{c.x, c.y, b.upper.z + e.z};
    on_plane.at = c;
    on_plane.fovy_degrees = 50.0f;
    cams.emplace_back("on-plane", on_plane);
    return cams;
}

void expect_no_mismatch(const oracle::Tally& t, const std::string& what) {
    EXPECT_EQ(t.mismatch, 0u) << what << ": " << oracle::summary(t);
    EXPECT_GT(t.total(), 0u) << what;
    if (t.mismatch > 0 && !t.examples.empty()) {
        const oracle::Example& ex = t.examples.front();
        ADD_FAILURE() << what << " first mismatch: ray " << ex.ray_index << " org " << ex.ray.org.x << ","
                      << ex.ray.org.y << "," << ex.ray.org.z << " dir " << ex.ray.dir.x << "," << ex.ray.dir.y << ","
                      << ex.ray.dir.z << " ours " << ex.ours.triangle << "@" << ex.ours.t << " oracle "
                      << ex.oracle.triangle << "@" << ex.oracle.t;
    }
}

void expect_same_answers(const workload::Engine& a, const workload::Engine& b, const workload::Workload& w, const std::string& what) {
    if (w.mode == workload::Mode::primary) {
        std::vector<Hit> ha, hb;
        a.intersect(w.rays, ha, 2);
        b.intersect(w.rays, hb, 1);
        for (std::size_t s = 0; s < ha.size(); ++s) {
            ASSERT_EQ(ha[s].triangle, hb[s].triangle) << what << " slot " << s;
            ASSERT_EQ(ha[s].t, hb[s].t) << what << " slot " << s;
        }
    } else {
        std::vector<std::uint8_t> oa, ob;
        a.occluded(w.rays, oa, 2);
        b.occluded(w.rays, ob, 1);
        ASSERT_EQ(oa, ob) << what;
    }
}

}  // namespace beamtrace::test
