#pragma once
// The whole public API.
#include "beamtrace/crsh.hpp"
#include "beamtrace/error.hpp"
#include "beamtrace/kdtree.hpp"
#include "beamtrace/mlrta.hpp"
#include "beamtrace/ray.hpp"
#include "beamtrace/ray_classification.hpp"
#include "beamtrace/scene.hpp"
#include "beamtrace/sorted_lists.hpp"
#include "beamtrace/stats.hpp"
#include "beamtrace/stream.hpp"
#include "beamtrace/vec.hpp"
#include "beamtrace/vlf.hpp"
