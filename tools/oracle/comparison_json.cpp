// A Tally as JSON.
#include "oracle/comparison_json.hpp"

#include <cmath>

namespace beamtrace::oracle {

namespace {

// JSON has no infinity or NaN: those become null.
nlohmann::json number(float x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json vec(Float3 p) { return nlohmann::json::array({number(p.x), number(p.y), number(p.z)}); }

nlohmann::json hit_json(const Hit& h) {
    if (!h.hit()) return {{"triangle", nullptr}};
    return {{"triangle", h.triangle}, {"t", number(h.t)}, {"u", number(h.u)}, {"v", number(h.v)}};
}

}  // namespace

nlohmann::json counts_json(const Tally& t) {
    return {{"agree", t.agree}, {"ties", t.ties}, {"grazing", t.grazing}, {"mismatch", t.mismatch}};
}

nlohmann::json examples_json(const Tally& t) {
    nlohmann::json out = nlohmann::json::array();
    for (const Example& e : t.examples) {
        nlohmann::json j = {{"ray_index", e.ray_index},
                            {"ray",
                             {{"org", vec(e.ray.org)},
                              {"dir", vec(e.ray.dir)},
                              {"tnear", number(e.ray.tnear)},
                              {"tfar", number(e.ray.tfar)}}}};
        if (e.occlusion) {
            j["ours_occluded"] = e.ours_occluded;
            j["oracle_occluded"] = e.oracle_occluded;
        } else {
            j["ours"] = hit_json(e.ours);
            j["oracle"] = hit_json(e.oracle);
        }
        out.push_back(std::move(j));
    }
    return out;
}

nlohmann::json to_json(const Tally& t) {
    nlohmann::json j = counts_json(t);
    j["total"] = t.total();
    j["examples"] = examples_json(t);
    return j;
}

}  // namespace beamtrace::oracle
