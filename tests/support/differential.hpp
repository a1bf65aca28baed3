#pragma once
// What every differential test against the Embree oracle shares: where the shared meshes are, the
// cameras each scene is checked from, and the assertion that a tally has no mismatch.
#include <string>
#include <utility>
#include <vector>

#include "engines/engine.hpp"
#include "oracle/comparison.hpp"
#include "rays/workload.hpp"
#include "scenes/scene_source.hpp"

namespace beamtrace::test {

// A mesh of ../shared/scenes by file name (BEAMTRACE_SCENES_DIR), or a generator spec unchanged.
std::string scene_path(const std::string& spec, bool shared_file);

// The scene's own camera, one inside at the centre of its box, one skimming the floor (the lowest
// y of the box) and one whose eye sits exactly on the box's centre planes.
std::vector<std::pair<std::string, scenes::Camera>> cameras_for(const scenes::SceneSource& source);

// Zero `mismatch` (and at least one ray); on failure the first mismatching ray is printed.
void expect_no_mismatch(const oracle::Tally& tally, const std::string& what);

// Engine a on two threads answers every slot of the workload as engine b on one: the same triangle
// and t for closest hits (primary), the same occlusion otherwise.
void expect_same_answers(const workload::Engine& a, const workload::Engine& b, const workload::Workload& w,
                         const std::string& what);

}  // namespace beamtrace::test
