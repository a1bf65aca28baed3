// vlf (VLF-RT, mode exact: every tile a ray crosses) and vlf-fast (mode fast: only the tile where
// the ray's segment starts, the paper's first description). Rays go through the field as streams of
// 4x4 packets (the library's span queries: SIMD lookups, fetches run ahead, one walk per ray, a
// contiguous stream per thread), in the given order or binned by PSF (--vlf-order).
#include <chrono>

#include "engines/engine_registry.hpp"

namespace beamtrace::workload {
namespace {

const char* order_name(VlfOrder o) {
    switch (o) {
        case VlfOrder::input:
            return "input";
        case VlfOrder::psf:
            return "psf";
        case VlfOrder::automatic:
            return "auto";
    }
    return "?";
}

class VlfEngine : public Engine {
public:
    explicit VlfEngine(VlfMode mode) : mode_(mode) {}
    std::string name() const override { return mode_ == VlfMode::exact ? "vlf" : "vlf-fast"; }

    void build(const Scene& scene, const EngineOptions& options) override {
        VlfOptions o = options.vlf;
        o.mode = mode_;
        const auto start = std::chrono::steady_clock::now();
        field_ =
            std::make_unique<VisibilityField>(scene, o, o.eager ? options.build_progress : VisibilityField::Progress{});
        construct_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        eager_psf_seconds_ = field_->stats().build_seconds;
    }
    // Construction (wall time, eager PSF builds included) plus every PSF built since by queries.
    double build_seconds() const override {
        return construct_seconds_ + (field_->stats().build_seconds - eager_psf_seconds_);
    }
    std::size_t memory_bytes() const override { return field_->stats().memory_bytes; }

    void trace(const RaySet& rays, bool closest, EngineAnswers& a, int threads) const override {
        answer_packets(*field_, rays, closest, a, QueryOptions{threads, nullptr});
    }

    nlohmann::json stats(const RaySet& rays) const override {
        QueryCounters c;
        EngineAnswers a;
        answer_packets(*field_, rays, closest_hit(rays.mode), a, QueryOptions{1, &c});
        const VlfStats s = field_->stats();
        const double n = c.rays ? double(c.rays) : 1.0;
        return {{"mode", mode_ == VlfMode::exact ? "exact" : "fast"},
                {"order", order_name(field_->options().order)},
                {"directions", s.directions},
                {"tiles", s.tiles},
                {"depth", s.depth},
                {"psfs_built", s.psfs_built},
                {"tile_entries", s.tile_entries},
                {"leaves", s.leaves},
                {"memory_bytes", s.memory_bytes},
                {"stream_bytes", s.stream_bytes},
                {"build_seconds", s.build_seconds},
                {"memory_budget_bytes", field_->options().memory_budget_bytes},
                {"memory_peak_bytes", s.memory_peak_bytes},
                {"lazy_tiles", field_->options().lazy_tiles},
                {"tiles_built", s.tiles_built},
                {"tiles_evicted", s.tiles_evicted},
                {"tiles_resident", s.tiles_resident},
                {"rebuild_seconds", s.rebuild_seconds},
                {"candidates_per_lookup", field_->directions().candidates_per_lookup()},
                {"mean_tiles_per_ray", double(c.vlf.tiles) / n},
                {"mean_leaves_per_ray", double(c.leaves) / n},
                {"mean_entries_per_ray", double(c.vlf.entries) / n},
                {"mean_triangle_tests_per_ray", double(c.triangle_tests) / n}};
    }

private:
    VlfMode mode_;
    std::unique_ptr<VisibilityField> field_;
    double construct_seconds_ = 0.0, eager_psf_seconds_ = 0.0;
};

}  // namespace

std::unique_ptr<Engine> make_vlf_engine(bool fast) {
    return std::make_unique<VlfEngine>(fast ? VlfMode::fast : VlfMode::exact);
}

}  // namespace beamtrace::workload
