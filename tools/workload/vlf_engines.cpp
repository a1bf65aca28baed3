// vlf (VLF-RT, mode exact: every tile a ray crosses) and vlf-fast (mode fast: only the tile where
// the ray's segment starts, the paper's first description). Rays go through the field as streams of
// 4x4 packets (SIMD lookups, fetches run ahead, one walk per ray), each thread a contiguous part,
// in the given order or binned by PSF (--vlf-order).
#include <algorithm>
#include <chrono>

#include "beamtrace/error.hpp"
#include "beamtrace/vlf.hpp"
#include "workload/engine_registry.hpp"
#include "workload/packet_answers.hpp"
#include "workload/parallel.hpp"

namespace beamtrace::workload {
namespace {

class VlfEngine : public Engine {
public:
    explicit VlfEngine(VlfMode mode) : mode_(mode) {}
    std::string name() const override { return mode_ == VlfMode::exact ? "vlf" : "vlf-fast"; }

    void build(const Scene& scene, const EngineOptions& options) override {
        if (options.vlf_order != "input" && options.vlf_order != "psf" && options.vlf_order != "auto")
            throw Error("VLF ray order must be input, psf or auto, not '" + options.vlf_order + "'");
        order_ = options.vlf_order;
        const auto start = std::chrono::steady_clock::now();
        field_ = std::make_unique<VisibilityField>(scene, options.vlf,
                                                   options.vlf.eager ? options.build_progress : VisibilityField::Progress{});
        construct_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        eager_psf_seconds_ = field_->stats().build_seconds;
    }
    // Construction (wall time, eager PSF builds included) plus every PSF built since by queries.
    double build_seconds() const override {
        return construct_seconds_ + (field_->stats().build_seconds - eager_psf_seconds_);
    }
    std::size_t memory_bytes() const override { return field_->stats().memory_bytes; }

    void intersect(const RaySet& rays, std::vector<Hit>& hits, int threads) const override {
        hits.assign(rays.slots(), Hit{});
        std::vector<PacketHits16>& out = packet_hits_;
        out.resize(rays.packets.size());
        const VlfOrder order = order_ == "psf" ? VlfOrder::psf : VlfOrder::input;
        // Rays in the given order go through the field in runs of kSpreadRun packets, each run's
        // answers spread into `hits` while they are still in the cache; binned rays (psf) in one
        // stream per thread, so that its bins are as full as they can be.
        const std::size_t run = order == VlfOrder::input ? kSpreadRun : rays.packets.size();
        for_contiguous_parts(rays.packets.size(), threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t c = b; c < e; c += run) {
                const std::size_t ce = std::min(e, c + run);
                field_->intersect(std::span(rays.packets).subspan(c, ce - c), std::span(out).subspan(c, ce - c), mode_,
                                  order);
                for (std::size_t p = c; p < ce; ++p) spread_hits(rays.packets[p], out[p], hits.data() + p * 16);
            }
        });
    }
    static constexpr std::size_t kSpreadRun = 1024;  // packets: 256 KB of answers

    void occluded(const RaySet& rays, std::vector<std::uint8_t>& occluded, int threads) const override {
        occluded.assign(rays.slots(), 0);
        std::vector<std::uint32_t>& bits = packet_bits_;
        bits.resize(rays.packets.size());
        const VlfOrder order = order_ == "input" ? VlfOrder::input : VlfOrder::psf;
        for_contiguous_parts(rays.packets.size(), threads, [&](std::size_t b, std::size_t e) {
            field_->occluded(std::span(rays.packets).subspan(b, e - b), std::span(bits).subspan(b, e - b), mode_, order);
        });
        for_packet_ranges(bits.size(), threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t p = b; p < e; ++p) spread_bits(bits[p], occluded.data() + p * 16);
        });
    }

    nlohmann::json stats(const RaySet& rays) const override {
        VlfCounters c;
        const bool closest = rays.mode == Mode::primary;
        for (std::size_t slot = 0; slot < rays.slots(); ++slot) {
            if (!rays.active(slot)) continue;
            if (closest) field_->intersect(rays.ray(slot), mode_, c);
            else field_->occluded(rays.ray(slot), mode_, c);
        }
        const VlfStats s = field_->stats();
        const double n = c.rays ? double(c.rays) : 1.0;
        return {{"mode", mode_ == VlfMode::exact ? "exact" : "fast"},
                {"directions", s.directions},
                {"tiles", s.tiles},
                {"depth", s.depth},
                {"psfs_built", s.psfs_built},
                {"tile_entries", s.tile_entries},
                {"leaves", s.leaves},
                {"memory_bytes", s.memory_bytes},
                {"stream_bytes", s.stream_bytes},
                {"build_seconds", s.build_seconds},
                {"candidates_per_lookup", field_->directions().candidates_per_lookup()},
                {"mean_tiles_per_ray", double(c.tiles) / n},
                {"mean_leaves_per_ray", double(c.leaves) / n},
                {"mean_entries_per_ray", double(c.entries) / n},
                {"mean_triangle_tests_per_ray", double(c.triangle_tests) / n}};
    }

private:
    // f(begin, end) on `threads` contiguous parts of the packets at once (each part a stream of
    // its own thread).
    template <class F>
    static void for_contiguous_parts(std::size_t packets, int threads, F&& f) {
        const std::size_t parts = std::size_t(std::max(1, threads));
        if (parts == 1) return f(std::size_t{0}, packets);
        tbb::task_arena arena{int(parts)};
        arena.execute([&] {
            tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t k) {
                f(packets * k / parts, packets * (k + 1) / parts);
            });
        });
    }

    VlfMode mode_;
    std::string order_ = "auto";
    // Per-packet answers, kept from one call to the next (like the callers' hit vectors) so that a
    // timed pass does not pay for fresh pages. Calls on one engine do not overlap.
    mutable std::vector<PacketHits16> packet_hits_;
    mutable std::vector<std::uint32_t> packet_bits_;
    std::unique_ptr<VisibilityField> field_;
    double construct_seconds_ = 0.0, eager_psf_seconds_ = 0.0;
};

}  // namespace

std::unique_ptr<Engine> make_vlf_engine(bool fast) { return std::make_unique<VlfEngine>(fast ? VlfMode::fast : VlfMode::exact); }

}  // namespace beamtrace::workload
