#pragma once
// The stream tracer's ray keys (ray_keys.hpp) written once over xsimd batches; included only by the
// per-ISA units. Each lane repeats make_keys_scalar's operations in the same order (contraction is
// off), so every key is the reference's bit for bit; the rays left over after the last whole batch
// go through the reference. Only xsimd functions and this file's internal-linkage helpers are used.
#include <cstdint>
#include <cstring>

#include <xsimd/xsimd.hpp>

#include "common/morton.hpp"
#include "common/ray_validity_impl.hpp"
#include "stream/ray_keys.hpp"

namespace beamtrace::stream {
namespace {

template <class Arch>
struct KeyLanes {
    using BF = xsimd::batch<float, Arch>;
    using BI = xsimd::batch<std::int32_t, Arch>;
    static constexpr std::size_t kSize = BF::size;

    // The reference's !(q > 0) ? 0 : q < 1023 ? unsigned(q) : 1023 (NaN gives 0).
    static BI cell(const BF& q) {
        const BF top(1023.0f);
        const BI i = xsimd::to_int(xsimd::select(q < top, q, top));
        return xsimd::select(xsimd::bool_cast(q > BF(0.0f)), i, BI(0));
    }
    // octahedral_code(dir, kPencilDirectionBits).
    static BI octahedral(const BF& dx, const BF& dy, const BF& dz) {
        const BF zero(0.0f), one(1.0f), half(0.5f);
        const BF l = (xsimd::abs(dx) + xsimd::abs(dy)) + xsimd::abs(dz);
        const BF u = dx / l, v = dy / l;
        const BF fu = (one - xsimd::abs(v)) * xsimd::select(u >= zero, one, BF(-1.0f));
        const BF fv = (one - xsimd::abs(u)) * xsimd::select(v >= zero, one, BF(-1.0f));
        const auto lower = dz < zero;
        const BF su = xsimd::select(lower, fu, u), sv = xsimd::select(lower, fv, v);
        const BF cells(float(1 << kPencilDirectionBits));
        return spread_bits_2(cell((su * half + half) * cells)) | (spread_bits_2(cell((sv * half + half) * cells)) << 1);
    }

    static void keys(const KeyInputs& in, const Ray* rays, std::size_t n, std::uint32_t* out) {
        constexpr std::size_t N = kSize;
        alignas(64) float c[8][N];  // org x, y, z, tnear, dir x, y, z, tfar of the batch's rays
        const BF zero(0.0f);
        const float r2 = in.radius * in.radius;
        std::size_t i = 0;
        for (; i + N <= n; i += N) {
            for (std::size_t l = 0; l < N; ++l) {
                float f[8];
                static_assert(sizeof(Ray) == sizeof(f));
                std::memcpy(f, &rays[i + l], sizeof(f));
                for (int k = 0; k < 8; ++k) c[k][l] = f[k];
            }
            const BF ox = BF::load_aligned(c[0]), oy = BF::load_aligned(c[1]), oz = BF::load_aligned(c[2]);
            const BF tn = BF::load_aligned(c[3]);
            const BF dx = BF::load_aligned(c[4]), dy = BF::load_aligned(c[5]), dz = BF::load_aligned(c[6]);
            const BF tf = BF::load_aligned(c[7]);
            const auto valid = simd::describes_segment_lanes<Arch>(ox, oy, oz, dx, dy, dz, tn, tf);
            BI key = BI(std::int32_t(kNoSegmentKey));
            auto cells = valid;  // lanes keyed by their origin's cell: no shared point takes them
            if (in.point_count > 0) {
                const auto finite_t = (tf - tf) == zero;
                const BF ex = xsimd::select(finite_t, ox + dx * tf, ox);
                const BF ey = xsimd::select(finite_t, oy + dy * tf, oy);
                const BF ez = xsimd::select(finite_t, oz + dz * tf, oz);
                BI point(0);
                for (int p = 0; p < in.point_count; ++p) {
                    const SharedPoint& s = in.points[p];
                    const BF sx(s.at.x), sy(s.at.y), sz(s.at.z);
                    decltype(cells) through;
                    if (!s.ends) {
                        through = (ox == sx) & (oy == sy) & (oz == sz);
                    } else {
                        const BF ddx = ex - sx, ddy = ey - sy, ddz = ez - sz;
                        through = finite_t & (((ddx * ddx + ddy * ddy) + ddz * ddz) <= BF(r2));
                    }
                    point = xsimd::select(xsimd::bool_cast(cells & through), BI(p), point);
                    cells = cells & !through;
                }
                const auto pencil = valid & !cells;
                if (xsimd::any(pencil)) {
                    const BI pencil_key =
                        BI(std::int32_t(kPencilBit)) | (point << kPointShift) | octahedral(dx, dy, dz);
                    key = xsimd::select(xsimd::bool_cast(pencil), pencil_key, key);
                }
            }
            if (xsimd::any(cells)) {  // rays through shared points (a light's shadow rays) need no cell
                const BI code = spread_bits_3(cell((ox - BF(in.lower[0])) * BF(in.scale[0]))) |
                                (spread_bits_3(cell((oy - BF(in.lower[1])) * BF(in.scale[1]))) << 1) |
                                (spread_bits_3(cell((oz - BF(in.lower[2])) * BF(in.scale[2]))) << 2);
                key = xsimd::select(xsimd::bool_cast(cells), code, key);
            }
            key.store_unaligned(reinterpret_cast<std::int32_t*>(out + i));
        }
        make_keys_scalar(in, rays + i, n - i, out + i);
    }
};

}  // namespace
}  // namespace beamtrace::stream
