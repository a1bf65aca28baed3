#pragma once
// VLF-RT (Mortensen, Khanna, Yu, Slater: "A Visibility Field for Ray Tracing", CGIV 2007): a set of
// beam directions over the hemisphere; for each direction a parallel subfield (PSF), an n x n grid
// of parallel beams ("tiles") over the scene's bounding sphere, each tile holding the triangles its
// beam meets, sorted along the beam by a 1D BSP (the tile-BSP). A ray looks up the PSF nearest its
// direction in constant time, walks the tiles its segment crosses front to back, and in each tile
// the tile-BSP leaves its segment spans, near to far.
//
// Mode exact walks every tile the ray crosses and answers exactly as the kd-tree does (same
// watertight triangle test, bit for bit). Mode fast uses only the tile where the ray's segment
// starts (the paper's first description, section 3.3) and can miss hits.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>

#include "beamtrace/query.hpp"
#include "beamtrace/ray.hpp"
#include "beamtrace/scene.hpp"
#include "beamtrace/vec.hpp"

namespace beamtrace {

namespace detail {
struct Access;  // the library's own access to the implementation (never part of the API)
}

// The beam directions Omega_l: l unit directions spread evenly over the upper hemisphere (z >= 0).
// Each stands for a line, so a direction d and -d share one PSF. Built as the grid points of an
// equal-area octahedral map of the hemisphere (half of the rim kept), which gives l = 2 m^2 + 1
// directions for m = 1..32 (9, 33, 129, 513, 2049 among them). nearest() takes constant time: a
// table over the hemisphere gives each cell the few directions that can be nearest within it.
class DirectionSet {
public:
    static constexpr int kDefaultCount = 513;
    // Throws beamtrace::Error naming the valid counts if count is not 2 m^2 + 1 with 1 <= m <= 32.
    explicit DirectionSet(int count = kDefaultCount);
    static bool valid_count(int count);

    int size() const;
    // Unit direction i (z >= 0; the half of the rim that is kept has y > 0, or y == 0 and x > 0).
    Float3 direction(int i) const;

    struct Nearest {
        std::uint32_t index = 0;  // the direction whose line makes the smallest angle with dir
        bool reversed = false;    // dir points along -direction(index)
    };
    // dir need not be normalised but must not be zero.
    Nearest nearest(Float3 dir) const;

    // Largest number of directions the lookup compares for one query (all queries compare this many).
    int candidates_per_lookup() const;
    std::size_t memory_bytes() const;

    struct Impl;  // opaque

private:
    friend struct detail::Access;
    std::shared_ptr<const Impl> impl_;
};

enum class VlfMode { exact, fast };
// The order in which a stream of packets is traced (see VisibilityField's span queries): as given,
// binned by PSF, or automatic (binned for occlusion queries, whose secondary rays are incoherent;
// as given for closest hits, whose packets are camera packets).
enum class VlfOrder { input, psf, automatic };

struct VlfOptions {
    int directions = DirectionSet::kDefaultCount;  // l
    int tiles = 128;                               // n: n x n tiles per PSF
    int depth = 4;                                 // d: tile-BSP depth, 0 = one leaf per tile
    bool eager = false;                            // build every PSF now (else each on first use)
    // Lazy tiles: a PSF builds each tile (its triangles and tile-BSP) the first time a ray reaches
    // it, not the whole PSF on its first use. The same tiles, word for word, and the same answers.
    bool lazy_tiles = true;
    // Bytes the field may hold (0 = unbounded): tiles, the least recently used first, are freed when
    // building another would exceed it, and rebuilt when a ray needs them again. Needs lazy tiles
    // and no eager build; must exceed the field's fixed part (triangles, direction tables, one
    // pointer per tile of every PSF).
    std::size_t memory_budget_bytes = 0;
    VlfMode mode = VlfMode::exact;                 // of the query contract's calls
    VlfOrder order = VlfOrder::automatic;          // of the query contract's span calls
    // The volume triangles may occupy, now and after dynamic updates. Default: the scene's box.
    std::optional<Box> bounds;
    // Throws beamtrace::Error naming the bad setting.
    void validate() const;
};

// Build statistics; PSFs are built on first use, so these grow as queries need more directions.
struct VlfStats {
    int directions = 0, tiles = 0, depth = 0;
    std::size_t psfs_built = 0;
    std::size_t tile_entries = 0;  // triangle ids over every leaf of every built PSF
    std::size_t leaves = 0;        // tile-BSP leaves over every built PSF
    std::size_t memory_bytes = 0;  // built PSFs, direction table, the field's copy of the triangles
    std::size_t stream_bytes = 0;  // buffers of binned occlusion streams, kept for the next stream
    double build_seconds = 0.0;    // over every PSF built so far (lazy builds included)
    // Lazy tiles (tile_entries and leaves above then count resident tiles only):
    std::size_t memory_peak_bytes = 0;  // the most memory_bytes has been (evicted tiles awaiting release included)
    std::size_t tiles_built = 0;        // tile builds, rebuilds after eviction included (empty tiles too)
    std::size_t tiles_evicted = 0;      // tiles freed under the memory budget
    std::size_t tiles_resident = 0;     // non-empty tiles held now
    double rebuild_seconds = 0.0;       // part of build_seconds spent rebuilding evicted tiles
};

// A 3x4 affine map p -> m * p + t (row-major m), applied to triangle corners in float.
struct Affine3 {
    float m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Float3 t;
    Float3 apply(Float3 p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + t.x,
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + t.y,
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + t.z};
    }
};

class VisibilityField {
public:
    // progress (optional) reports the eager build in [0, 1]. Throws beamtrace::Error for bad options
    // and for a scene of more than 2^24 triangles (tile entries keep 3-byte triangle ids).
    using Progress = std::function<void(double)>;
    explicit VisibilityField(const Scene& scene, const VlfOptions& options = {}, const Progress& progress = {});
    ~VisibilityField();
    VisibilityField(VisibilityField&&) noexcept;
    VisibilityField& operator=(VisibilityField&&) noexcept;

    // The query contract (query.hpp), in options().mode; span calls in options().order. Thread-safe
    // (PSFs are built under a lock the first time a query needs them). Span calls run as streams:
    // the lookups of 16 rays at a time (direction, canonical ray, first tile) run as SIMD, then each
    // ray walks its own tiles, while the lookups, tile entries, blocks and first triangles of the
    // next packets are fetched from memory; VlfOrder::psf first bins the rays by the PSF their
    // lookup picks and, within a PSF, by the tile where they start (counting sorts), so that each
    // PSF's tiles are read front to back while they are in the cache. QueryOptions::threads splits a
    // stream into that many contiguous streams. With QueryOptions::counters the rays are counted
    // one by one by the single-ray walk (the same walk code) instead.
    Hit intersect(const Ray& ray) const;
    bool occluded(const Ray& ray) const;
    void intersect(std::span<const Ray> rays, std::span<Hit> hits, const QueryOptions& options = {}) const;
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded, const QueryOptions& options = {}) const;
    void intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits,
                   const QueryOptions& options = {}) const;
    void occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded,
                  const QueryOptions& options = {}) const;

    // The same queries in a given mode (and order), on one thread; inactive rays report no hit,
    // bit i of an occlusion word = ray i occluded. The counting single-ray calls add to counters
    // (rays, leaves, triangle_tests, vlf.tiles, vlf.entries).
    Hit intersect(const Ray& ray, VlfMode mode) const;
    bool occluded(const Ray& ray, VlfMode mode) const;
    Hit intersect(const Ray& ray, VlfMode mode, QueryCounters& counters) const;
    bool occluded(const Ray& ray, VlfMode mode, QueryCounters& counters) const;
    void intersect(const Packet16& packet, PacketHits16& hits, VlfMode mode = VlfMode::exact) const;
    std::uint32_t occluded(const Packet16& packet, VlfMode mode = VlfMode::exact) const;
    void intersect(std::span<const Packet16> packets, std::span<PacketHits16> hits, VlfMode mode,
                   VlfOrder order = VlfOrder::psf) const;
    void occluded(std::span<const Packet16> packets, std::span<std::uint32_t> occluded, VlfMode mode,
                  VlfOrder order = VlfOrder::psf) const;

    // What a field of `triangles` triangles with these options holds before any tile is built, with
    // lazy tiles and every PSF's tile table allocated: a memory budget must exceed it (by 64 KiB at
    // least; under a budget an eighth of it, where it can be spared, goes to binned streams).
    static std::size_t fixed_memory_bytes(std::size_t triangles, const VlfOptions& options);

    // Builds every PSF (with lazy tiles: every tile) not built yet (TBB, all cores), reporting
    // progress in [0, 1]. Throws beamtrace::Error under a memory budget.
    void build_all(const Progress& progress = {});

    // Dynamic scenes (section 8): take triangles out of every built PSF, move them, put them back.
    // Each updates the built PSFs in place; PSFs built later see the current geometry. Not to be
    // called while queries run. Throws beamtrace::Error for an id out of range, removing a triangle
    // twice, inserting one that is in, transforming one that is in, or inserting one outside bounds.
    void remove(std::span<const std::uint32_t> ids);
    void transform(std::span<const std::uint32_t> ids, const Affine3& map);
    void insert(std::span<const std::uint32_t> ids);
    // Current corners of every triangle (removed ones included) and whether it is in the field.
    std::span<const Triangle> triangles() const;
    bool contains(std::uint32_t id) const;

    const DirectionSet& directions() const;
    const VlfOptions& options() const;
    VlfStats stats() const;

    struct Impl;  // opaque

private:
    friend struct detail::Access;
    std::unique_ptr<Impl> impl_;
};

}  // namespace beamtrace
