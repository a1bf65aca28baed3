// The Embree engines' timed passes over ray sets prebuilt in parts (EngineOptions::embree_part_packets):
// the same answers, slot for slot and bit for bit, as the whole set prebuilt at once, for every layout,
// both query kinds, both context flags and one or two threads; and the stats say what one part held.
// Also: engines given the caller's Embree scene (EngineOptions::embree_scene) trace it only when it
// was built alike, and answer as with their own.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "beamtrace/error.hpp"
#include "engines/engine.hpp"
#include "oracle/embree_native_rays.hpp"
#include "rays/workload.hpp"

using namespace beamtrace;
using namespace beamtrace::workload;

namespace {

bool same_bits(const Hit& a, const Hit& b) {
    return std::memcmp(&a.t, &b.t, sizeof(float)) == 0 && a.triangle == b.triangle &&
           std::memcmp(&a.u, &b.u, sizeof(float)) == 0 && std::memcmp(&a.v, &b.v, sizeof(float)) == 0;
}

Workload make(Mode mode) {
    WorkloadConfig config;
    config.scene = "tetra:3";
    config.mode = mode;
    config.width = 40;  // 10 x 10 packets of 4 x 4: 100 packets, parts of 7 leave a part of 2
    config.height = 40;
    config.ao_rays = 4;
    return make_workload(config);
}

}  // namespace

TEST(EmbreeEngineParts, PassesInPartsAnswerAsTheWholeSetBitForBit) {
    for (Mode mode : {Mode::primary, Mode::shadow, Mode::ao}) {
        const Workload w = make(mode);
        const bool closest = closest_hit(mode);
        ASSERT_GT(w.rays.packets.size(), 7u * 3);
        for (const char* name : {"embree1", "embree16", "embree-stream"}) {
            auto whole = make_engine(name), parts = make_engine(name);
            EngineOptions options;
            whole->build(w.source.scene, options);
            options.embree_part_packets = 7;
            parts->build(w.source.scene, options);
            for (int threads : {1, 2})
                for (int variant = 0; variant < int(whole->timing_variants().size()); ++variant) {
                    const std::string what = std::string(name) + " " + to_string(mode) + " threads " +
                                             std::to_string(threads) + " variant " + std::to_string(variant);
                    EngineAnswers a, b;
                    EXPECT_GE(whole->timed_pass(w.rays, a, threads, variant), 0.0) << what;
                    EXPECT_GE(parts->timed_pass(w.rays, b, threads, variant), 0.0) << what;
                    ASSERT_EQ(b.form, EngineAnswers::Form::slots) << what;
                    std::size_t answered = 0;
                    if (closest) {
                        ASSERT_EQ(a.hits.size(), w.rays.slots()) << what;
                        ASSERT_EQ(b.hits.size(), w.rays.slots()) << what;
                        for (std::size_t s = 0; s < w.rays.slots(); ++s) {
                            EXPECT_TRUE(same_bits(a.hits[s], b.hits[s])) << what << " slot " << s;
                            EXPECT_TRUE(same_bits(b.hits[s], w.reference_hits[s])) << what << " slot " << s;
                            answered += b.hits[s].hit();
                        }
                    } else {
                        ASSERT_EQ(b.occluded.size(), w.rays.slots()) << what;
                        for (std::size_t s = 0; s < w.rays.slots(); ++s) {
                            EXPECT_EQ(a.occluded[s], b.occluded[s]) << what << " slot " << s;
                            EXPECT_EQ(b.occluded[s], w.reference_occluded[s]) << what << " slot " << s;
                            answered += b.occluded[s];
                        }
                    }
                    EXPECT_GT(answered, 0u) << what << ": the scene is hit, so some rays must be answered";
                }
            // What one part held, not the whole set's layout.
            const nlohmann::json whole_stats = whole->stats(w.rays), part_stats = parts->stats(w.rays);
            ASSERT_TRUE(part_stats.contains("ray_layout_part_rays")) << name;
            EXPECT_EQ(part_stats["ray_layout_part_rays"].get<std::size_t>(), 7u * 16);
            EXPECT_FALSE(whole_stats.contains("ray_layout_part_rays")) << name;
            const auto part_bytes = part_stats["ray_layout_bytes"].get<std::size_t>();
            const auto whole_bytes = whole_stats["ray_layout_bytes"].get<std::size_t>();
            EXPECT_LT(part_bytes, whole_bytes) << name << " " << to_string(mode);
            // Primary rays fill every packet: a part of 7 of the 100 packets holds 7 % of the layout.
            if (mode == Mode::primary) {
                EXPECT_LT(part_bytes * 10, whole_bytes) << name;
            }
        }
    }
}

TEST(EmbreeEngineParts, AnswerSpansOfTheWrongSizeAreRefused) {
    const Workload w = make(Mode::primary);
    auto engine = make_engine("embree16");
    engine->build(w.source.scene, EngineOptions{});
    EngineAnswers answers;
    engine->timed_pass(w.rays, answers, 1, 0);
    // The span form of the native rays checks its size; a bench pass never gives a wrong one, so
    // exercise it through the oracle layer directly.
    oracle::EmbreeOracle oracle(w.source.scene);
    oracle::EmbreeNativeRays native(oracle, oracle::EmbreeLayout::packet16, w.rays.packets, true);
    std::vector<Hit> short_answers(w.rays.slots() - 1);
    try {
        native.hits(std::span<Hit>(short_answers));
        FAIL() << "a span one slot short was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("answer slots"), std::string::npos) << e.what();
    }
    std::vector<std::uint8_t> occluded(w.rays.slots());
    EXPECT_THROW(native.occluded(std::span<std::uint8_t>(occluded)), Error);  // made for closest hits
}

TEST(EmbreeEngineParts, EnginesTraceTheCallersSceneOnlyWhenBuiltAlike) {
    const Workload w = make(Mode::primary);
    for (const char* name : {"embree1", "embree16", "embree-stream"})
        for (bool robust : {true, false}) {
            const std::string what = std::string(name) + (robust ? " robust" : " not robust");
            auto engine = make_engine(name);
            EngineOptions options;
            options.embree_robust = robust;
            options.embree_scene = w.oracle;  // robust, Embree's default threads
            engine->build(w.source.scene, options);
            const nlohmann::json stats = engine->stats(w.rays);
            EXPECT_EQ(stats["scene_shared"].get<bool>(), robust) << what;
            EXPECT_EQ(stats["robust"].get<bool>(), robust) << what;
            EXPECT_GT(engine->build_seconds(), 0.0) << what << ": its own build is timed either way";
            EXPECT_GT(engine->memory_bytes(), 0u) << what;
            EngineAnswers answers;
            engine->timed_pass(w.rays, answers, 1, 0);
            ASSERT_EQ(answers.hits.size(), w.rays.slots()) << what;
            std::size_t differ = 0;
            for (std::size_t s = 0; s < w.rays.slots(); ++s)
                differ += answers.hits[s].triangle != w.reference_hits[s].triangle;
            EXPECT_EQ(differ, 0u) << what;
        }
    // Another thread count for the builder is another build: not shared.
    auto engine = make_engine("embree16");
    EngineOptions options;
    options.embree_build_threads = 1;
    options.embree_scene = w.oracle;
    engine->build(w.source.scene, options);
    EXPECT_FALSE(engine->stats(w.rays)["scene_shared"].get<bool>());
}
