#include "engines/engine_registry.hpp"

#include "beamtrace/error.hpp"

namespace beamtrace::workload {

const std::vector<std::string>& engine_names() {
    static const std::vector<std::string> names = {"embree1", "embree16", "embree-stream", "brute",   "kd1",
                                                   "kd16",    "mlrta",    "vlf",           "vlf-fast",
                                                   "stream",  "embree-sorted", "crsh",     "rah",
                                                   "raycls",  "lists",    "lists-flat"};
    return names;
}

std::unique_ptr<Engine> make_engine(const std::string& name) {
    if (name == "embree1") return make_embree_engine(oracle::EmbreeLayout::single);
    if (name == "embree16") return make_embree_engine(oracle::EmbreeLayout::packet16);
    if (name == "embree-stream") return make_embree_engine(oracle::EmbreeLayout::stream);
    if (name == "brute") return make_brute_engine();
    if (name == "kd1") return make_kd1_engine();
    if (name == "kd16") return make_kd16_engine();
    if (name == "mlrta") return make_mlrta_engine();
    if (name == "vlf") return make_vlf_engine(false);
    if (name == "vlf-fast") return make_vlf_engine(true);
    if (name == "stream") return make_stream_engine();
    if (name == "embree-sorted") return make_embree_sorted_engine();
    if (name == "crsh") return make_crsh_engine(true);
    if (name == "rah") return make_crsh_engine(false);
    if (name == "raycls") return make_raycls_engine();
    if (name == "lists") return make_lists_engine(false);
    if (name == "lists-flat") return make_lists_engine(true);
    std::string known;
    for (const std::string& n : engine_names()) known += (known.empty() ? "" : ", ") + n;
    throw Error("unknown engine '" + name + "' (known: " + known + ")");
}

}  // namespace beamtrace::workload
