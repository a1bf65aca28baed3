// libFuzzer target: the scene API with hostile arrays, then a kd-tree over what it accepts and a few
// rays through it. The API trusts the caller's array sizes (it cannot see them), so the arrays
// handed over are always as long as the counts say; everything else comes from the input: counts
// (zero, huge), coordinates (NaN, infinities, denormals, 3e38), indices (out of range, repeated),
// null pointers. Accepted scenes must have consistent sizes and boxes; rejections must be
// beamtrace::Error. Any other exception, a crash, or a sanitizer report is a finding.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "beamtrace/error.hpp"
#include "beamtrace/kdtree.hpp"
#include "beamtrace/scene.hpp"

namespace {

// Reads values from the input, zeros once it is used up.
class Input {
public:
    Input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
    template <class T>
    T take() {
        T value{};
        const std::size_t n = std::min(sizeof(T), size_ - pos_);
        std::memcpy(&value, data_ + pos_, n);
        pos_ += n;
        return value;
    }
    bool empty() const { return pos_ >= size_; }

private:
    const std::uint8_t* data_;
    std::size_t size_, pos_ = 0;
};

void check(bool ok) {
    if (!ok) __builtin_trap();
}

void use(const beamtrace::Scene& scene, Input& in) {
    check(scene.triangle_count() > 0 && scene.vertex_count() > 0);
    check(scene.indices().size() == 3 * scene.triangle_count());
    check(scene.degenerate_count() <= scene.triangle_count());
    const beamtrace::Box& b = scene.bounds();
    for (int k = 0; k < 3; ++k)
        check(std::isfinite(b.lower[k]) && std::isfinite(b.upper[k]) && b.lower[k] <= b.upper[k]);
    // The builder and the single-ray traversal on whatever geometry came through.
    const beamtrace::KdTree tree = beamtrace::KdTree::build(scene);
    for (int i = 0; i < 8 && !in.empty(); ++i) {
        beamtrace::Ray r;
        r.org = {in.take<float>(), in.take<float>(), in.take<float>()};
        r.dir = {in.take<float>(), in.take<float>(), in.take<float>()};
        r.tnear = in.take<float>();
        r.tfar = in.take<float>();
        const beamtrace::Hit h = tree.intersect(r);
        if (h.hit()) check(h.triangle < scene.triangle_count() && !scene.is_degenerate(h.triangle));
        tree.occluded(r);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    Input in(data, size);
    const std::uint8_t mode = in.take<std::uint8_t>();
    // Counts: small ones mostly (arrays are built to match), huge ones only with null pointers.
    std::size_t vertices = in.take<std::uint16_t>() % 512;
    std::size_t triangles = in.take<std::uint16_t>() % 512;
    std::vector<float> xyz(3 * vertices);
    for (float& f : xyz) f = in.take<float>();
    std::vector<std::uint32_t> indices(3 * triangles);
    for (std::uint32_t& i : indices) {
        const std::uint32_t raw = in.take<std::uint32_t>();
        // Mostly valid indices, so that deeper code is reached; raw ones too.
        i = (raw & 0x80000000u) || vertices == 0 ? raw : raw % std::uint32_t(vertices);
    }
    try {
        switch (mode % 4) {
            case 0: {
                const beamtrace::Scene scene(xyz.data(), vertices, indices.data(), triangles);
                use(scene, in);
                break;
            }
            case 1: {  // the span form, with an index count that may not be a multiple of 3
                const std::size_t n = indices.size() - std::min<std::size_t>(indices.size(), mode / 4 % 3);
                std::vector<beamtrace::Float3> points(vertices);
                if (!xyz.empty()) std::memcpy(points.data(), xyz.data(), xyz.size() * sizeof(float));
                const beamtrace::Scene scene(std::span<const beamtrace::Float3>(points),
                                             std::span<const std::uint32_t>(indices.data(), n));
                use(scene, in);
                break;
            }
            case 2: {  // null pointers with any counts, huge ones included: must throw before reading
                const std::size_t huge_v = in.take<std::uint64_t>(), huge_t = in.take<std::uint64_t>();
                const bool null_v = mode & 16, null_i = mode & 64;
                const beamtrace::Scene scene(null_v ? nullptr : xyz.data(), null_v && (mode & 32) ? huge_v : vertices,
                                             null_i ? nullptr : indices.data(),
                                             null_i && (mode & 128) ? huge_t : triangles);
                check(!null_v && !null_i);  // only real arrays can make a scene
                use(scene, in);
                break;
            }
            default: {  // every vertex from a few distinct values: coincident and degenerate geometry
                const float values[4] = {in.take<float>(), in.take<float>(), 0.0f, -0.0f};
                for (std::size_t i = 0; i < xyz.size(); ++i) xyz[i] = values[(std::size_t(data[i % size]) >> 3) % 4];
                const beamtrace::Scene scene(xyz.data(), vertices, indices.data(), triangles);
                use(scene, in);
                break;
            }
        }
    } catch (const beamtrace::Error&) {
        // A clear rejection: what the API promises.
    }
    return 0;
}
