#pragma once
// A Tally as JSON for reports.
#include <nlohmann/json.hpp>

#include "oracle/comparison.hpp"

namespace beamtrace::oracle {

// {"agree": n, "ties": n, "grazing": n, "mismatch": n}
nlohmann::json counts_json(const Tally& tally);

// The kept mismatches: [{"ray_index", "ray": {"org", "dir", "tnear", "tfar"}, then for closest-hit
// rays "ours"/"oracle": {"triangle" (null for a miss), "t", "u", "v"}, for occlusion rays
// "ours_occluded"/"oracle_occluded"}].
nlohmann::json examples_json(const Tally& tally);

// Both: counts_json plus "total" and "examples".
nlohmann::json to_json(const Tally& tally);

}  // namespace beamtrace::oracle
