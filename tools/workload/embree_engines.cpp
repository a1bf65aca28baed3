// embree1 and embree16: Embree 3 through the oracle, single rays and 4x4 packets.
#include <chrono>

#include "oracle/embree_oracle.hpp"
#include "workload/engine_registry.hpp"
#include "workload/packet_answers.hpp"
#include "workload/parallel.hpp"

namespace beamtrace::workload {
namespace {

class EmbreeEngine : public Engine {
public:
    explicit EmbreeEngine(bool packets) : packets_(packets) {}
    std::string name() const override { return packets_ ? "embree16" : "embree1"; }
    void build(const Scene& scene, const EngineOptions&) override { oracle_ = std::make_unique<oracle::EmbreeOracle>(scene); }
    double build_seconds() const override { return oracle_->build_seconds(); }
    std::size_t memory_bytes() const override { return oracle_->memory_bytes(); }

    void intersect(const RaySet& rays, std::vector<Hit>& hits, int threads) const override {
        hits.assign(rays.slots(), Hit{});
        for_packet_ranges(rays.packets.size(), threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t p = b; p < e; ++p) {
                const Packet16& packet = rays.packets[p];
                if (packets_) {
                    PacketHits16 out;
                    oracle_->intersect16(packet, out);
                    spread_hits(packet, out, hits.data() + p * 16);
                } else {
                    for (std::uint32_t m = packet.active; m; m &= m - 1) {
                        const int i = __builtin_ctz(m);
                        hits[p * 16 + std::size_t(i)] = oracle_->intersect1(packet.ray(i));
                    }
                }
            }
        });
    }

    void occluded(const RaySet& rays, std::vector<std::uint8_t>& occluded, int threads) const override {
        occluded.assign(rays.slots(), 0);
        for_packet_ranges(rays.packets.size(), threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t p = b; p < e; ++p) {
                const Packet16& packet = rays.packets[p];
                if (packets_) {
                    spread_bits(oracle_->occluded16(packet), occluded.data() + p * 16);
                } else {
                    for (std::uint32_t m = packet.active; m; m &= m - 1) {
                        const int i = __builtin_ctz(m);
                        occluded[p * 16 + std::size_t(i)] = oracle_->occluded1(packet.ray(i));
                    }
                }
            }
        });
    }

    nlohmann::json stats(const RaySet&) const override {
        return {{"embree_triangles", oracle_->embree_triangle_count()}};
    }

private:
    bool packets_;
    std::unique_ptr<oracle::EmbreeOracle> oracle_;
};

}  // namespace

std::unique_ptr<Engine> make_embree_engine(bool packets) { return std::make_unique<EmbreeEngine>(packets); }

}  // namespace beamtrace::workload
