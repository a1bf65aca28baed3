#pragma once
// Constructors of the engines, one per file; make_engine() (engine_registry.cpp) picks by name.
#include <memory>

#include "engines/engine.hpp"
#include "oracle/embree_native_rays.hpp"

namespace beamtrace::workload {

std::unique_ptr<Engine> make_embree_engine(oracle::EmbreeLayout layout);
std::unique_ptr<Engine> make_brute_engine();
std::unique_ptr<Engine> make_kd1_engine();
std::unique_ptr<Engine> make_kd16_engine();
std::unique_ptr<Engine> make_mlrta_engine();
std::unique_ptr<Engine> make_vlf_engine(bool fast);
std::unique_ptr<Engine> make_stream_engine();
std::unique_ptr<Engine> make_embree_sorted_engine();

// The kd-tree of the engines that trace packets (kd16, stream): built with the options' rules and
// triangle culling, its packet tables made.
std::unique_ptr<KdTree> build_packet_tree(const Scene& scene, const EngineOptions& options);

// The kd-tree's build statistics (kd1, kd16, stream).
nlohmann::json tree_json(const KdBuildStats& stats);
// crsh (sort = true: CRSH with object spheres) or rah (Roger et al.: input order, no object spheres).
std::unique_ptr<Engine> make_crsh_engine(bool sort);
// raycls: ray classification (5D ray space, light buffers).
std::unique_ptr<Engine> make_raycls_engine();
// lists (the hierarchy of sorted lists) or lists-flat (one level).
std::unique_ptr<Engine> make_lists_engine(bool flat);

// The statistics kd16 and mlrta report alike (the paper's Tables 2 and 3): cells, entry-point
// cells and intersections per packet and the other packet counters; and MLRTA's settings.
nlohmann::json packet_counters_json(const QueryCounters& counters, std::size_t kd_nodes, bool triangle_culling);
nlohmann::json mlrta_settings_json(const MlrtaSettings& settings);

}  // namespace beamtrace::workload
