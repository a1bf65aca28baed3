#pragma once
// The moving triangles of an AnimatedScene over one time bin [t0, t1]: a 5D tree (32 children a
// level, as the static 5D tree) whose candidates are the triangles' swept boxes over the bin, made
// lazily where rays arrive; and, for calls whose rays share an end or start point, light buffers
// around that point (origins not split: 4 children a level, deeper). A ray at time t in the bin
// tests its cell's candidates placed at t.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "beamtrace/animated_scene.hpp"
#include "beamtrace/query.hpp"
#include "common/triangle_kernels.hpp"
#include "raycls/ray_space.hpp"
#include "raycls/shared_point.hpp"

namespace beamtrace::raycls {

struct MovingCandidate {
    Box swept;  // the triangle at every time of the bin
    float key;  // s * the box's nearest coordinate on the face axis
    std::uint32_t index;  // into MovingContext::moving
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

// A light buffer's face: a uniform n x n grid over the face's (u, v) square, each cell listing the
// candidates whose direction rectangle seen from the apex box meets it (padded), in key order, side
// by side (offsets per cell); candidates whose rectangle covers more than a sixteenth of the face go
// to `wide`, which every ray of the face scans too. Made in one pass over the bin's candidates.
struct MovingGrid {
    int n = 1;
    std::vector<std::uint32_t> offsets;  // n * n + 1
    std::vector<MovingCandidate> items, wide;
    int index(float u, float v) const {
        const float half = 0.5f * float(n);
        const int i = std::clamp(int((u + 1.0f) * half), 0, n - 1), j = std::clamp(int((v + 1.0f) * half), 0, n - 1);
        return j * n + i;
    }
    std::size_t bytes() const {
        return sizeof(MovingGrid) + offsets.capacity() * sizeof(std::uint32_t) +
               (items.capacity() + wide.capacity()) * sizeof(MovingCandidate);
    }
};

// One structure of a bin: the 5D tree over `origins` (split_origins) or a light buffer around a
// point (the apex box `origins`): a direction grid per face.
struct MovingTree {
    Box origins;
    bool split_origins = true;
    int max_depth = 4;
    std::atomic<MovingCell*> roots[6] = {};  // made when a ray first takes a face
    std::atomic<MovingGrid*> grids[6] = {};  // light buffers: made when a ray first takes a face
};

// Every moving triangle of the context at time t (AnimatedScene::triangle_at), by index.
void place_moving(const MovingContext& context, float t, std::vector<Triangle>& out);

class MovingBin {
public:
    MovingBin(MovingContext& context, float t0, float t1);
    ~MovingBin();
    MovingBin(const MovingBin&) = delete;
    MovingBin& operator=(const MovingBin&) = delete;

    // Closest hit of the ray at `time` among the moving triangles, better than `best` (smaller t, at
    // equal t smaller id); returns best when none is. Occlusion: any hit within the segment.
    // placed: every moving triangle at `time` (by index into MovingContext::moving, made by
    // place_moving), or null to place each candidate as it is tested.
    // tree: space_tree() or a light_buffer() of this bin; frame: how the ray is classified in it.
    template <bool kCount>
    Hit closest(const Ray& ray, float time, const Triangle* placed, Hit best, QueryCounters* counters,
                const MovingTree& tree, Frame frame) const;
    template <bool kCount>
    bool any(const Ray& ray, float time, const Triangle* placed, QueryCounters* counters, const MovingTree& tree,
             Frame frame) const;

    const MovingTree& space_tree() const { return space_; }
    // The light buffer whose apex holds `points` (made when missing), or the 5D tree when there are
    // too many already.
    const MovingTree& light_buffer(const Box& points, float grow) const;

    std::atomic<std::uint64_t> last_used{0};

private:
    // The ray's cell, its candidates in order; kAny: the first hit of the segment.
    template <bool kAny, bool kCount>
    Hit scan(const Ray& ray, float time, const Triangle* placed, Hit best, QueryCounters* counters,
             const MovingTree& tree, Frame frame) const;
    const MovingCell* cell_of(const MovingTree& tree, const float p[3], const DirectionCode& code) const;
    MovingCell* make_root(const MovingTree& tree, int face) const;
    MovingGrid* make_grid(const MovingTree& tree, int face) const;
    const MovingGrid& grid_of(const MovingTree& tree, int face) const;
    MovingCell* make_child(const MovingTree& tree, const MovingCell& parent, int index) const;
    void delete_cell(MovingCell* c) const;
    void delete_tree(MovingTree& tree) const;
    std::size_t bytes_of(const MovingCell& c) const;

    MovingContext& context_;
    std::vector<Box> swept_;  // every moving triangle's box over the bin, by index
    MovingTree space_;
    mutable std::mutex buffers_mutex_;
    mutable std::vector<std::unique_ptr<MovingTree>> buffers_;
};

}  // namespace beamtrace::raycls
