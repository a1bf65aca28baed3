#pragma once
// The moving triangles of an AnimatedScene over one time bin [t0, t1]: a 5D tree (32 children a
// level, as the static 5D tree) whose candidates are the triangles' swept boxes over the bin, made
// lazily where rays arrive. A ray at time t in the bin tests its cell's candidates placed at t.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "beamtrace/animated_scene.hpp"
#include "beamtrace/query.hpp"
#include "common/triangle_kernels.hpp"
#include "raycls/ray_space.hpp"

namespace beamtrace::raycls {

struct MovingCandidate {
    Box swept;  // the triangle at every time of the bin
    float key;  // s * the box's nearest coordinate on the face axis
    std::uint32_t id;
};

struct MovingCell {
    CellBounds bounds;
    std::vector<MovingCandidate> items;
    bool final = false;
    int depth = 0;
    std::unique_ptr<std::atomic<MovingCell*>[]> children;  // 32 unless final
};

// What the bins of one classification share.
struct MovingContext {
    const AnimatedScene* scene = nullptr;
    const TriangleKernels* kernels = nullptr;
    const std::vector<std::uint32_t>* moving = nullptr;  // ids of the moving triangles
    Box origins;                                         // every triangle at every time
    int max_depth = 4, min_candidates = 6;
    double origin_margin = 0.0, direction_margin = 0.0;
    std::atomic<std::size_t> bytes{0}, peak_bytes{0};
    std::atomic<std::uint64_t> cells{0}, entries{0};

    void add(std::size_t b, std::size_t n);
    void remove(std::size_t b, std::size_t n);
};

class MovingBin {
public:
    MovingBin(MovingContext& context, float t0, float t1);
    ~MovingBin();
    MovingBin(const MovingBin&) = delete;
    MovingBin& operator=(const MovingBin&) = delete;

    // Closest hit of the ray at `time` among the moving triangles, better than `best` (smaller t, at
    // equal t smaller id); returns best when none is. Occlusion: any hit within the segment.
    template <bool kCount>
    Hit closest(const Ray& ray, float time, Hit best, QueryCounters* counters) const;
    template <bool kCount>
    bool any(const Ray& ray, float time, QueryCounters* counters) const;

    std::atomic<std::uint64_t> last_used{0};

private:
    // The ray's cell, its candidates in order; kAny: the first hit of the segment.
    template <bool kAny, bool kCount>
    Hit scan(const Ray& ray, float time, Hit best, QueryCounters* counters) const;
    const MovingCell* cell_of(const Ray& ray, float& key_origin, float& step) const;
    MovingCell* make_child(const MovingCell& parent, int index) const;
    void delete_cell(MovingCell* c) const;
    std::size_t bytes_of(const MovingCell& c) const;

    MovingContext& context_;
    std::unique_ptr<MovingCell> roots_[6];
};

}  // namespace beamtrace::raycls
