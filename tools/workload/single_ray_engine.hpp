#pragma once
// Engines that answer one ray at a time: the loops over packets and lanes written once.
#include "workload/engine.hpp"
#include "workload/parallel.hpp"

namespace beamtrace::workload {

class SingleRayEngine : public Engine {
public:
    void intersect(const RaySet& rays, std::vector<Hit>& hits, int threads) const override {
        hits.assign(rays.slots(), Hit{});
        for_packet_ranges(rays.packets.size(), threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t p = b; p < e; ++p)
                for (std::uint32_t m = rays.packets[p].active; m; m &= m - 1) {
                    const int i = __builtin_ctz(m);
                    hits[p * 16 + std::size_t(i)] = intersect_one(rays.packets[p].ray(i));
                }
        });
    }
    void occluded(const RaySet& rays, std::vector<std::uint8_t>& occluded, int threads) const override {
        occluded.assign(rays.slots(), 0);
        for_packet_ranges(rays.packets.size(), threads, [&](std::size_t b, std::size_t e) {
            for (std::size_t p = b; p < e; ++p)
                for (std::uint32_t m = rays.packets[p].active; m; m &= m - 1) {
                    const int i = __builtin_ctz(m);
                    occluded[p * 16 + std::size_t(i)] = occluded_one(rays.packets[p].ray(i));
                }
        });
    }

protected:
    virtual Hit intersect_one(const Ray& ray) const = 0;
    virtual bool occluded_one(const Ray& ray) const = 0;
};

}  // namespace beamtrace::workload
