#pragma once

// Private: the 4-lane watertight triangle test of a TriangleBlock (SSE2), the leaf half of
// the SSE, AVX2 and AVX-512 wide kernels. Baseline code: the AVX kernels' entry points are
// flattened, so there it is inlined with the VEX encoding.
//
// Lane by lane it performs the float operations of triangle.h's intersect() in the same
// order (the library is built with -ffp-contract=off, so no product is fused into an
// FMA behind our back): the t, u and v it returns are bit-identical to the scalar test's.

#include "ablation.h"
#include "wide_bvh.h"

#include <librt/geometry/ray.h>
#include <librt/geometry/triangle.h>

#include <immintrin.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <utility>

namespace librt::detail {

/// Per-ray constants of the 4-lane test: triangle.h's permutation and shear, broadcast.
struct TriRay4 {
    __m128 o_kx, o_ky, o_kz;  ///< origin components along the permuted axes
    __m128 sx, sy, sz;
    /// Byte offsets of the rows of axes kx, ky, kz within a corner of a TriangleBlock
    /// (16 k): a row is one load at block + 48 corner + offset. Axis indices made every leaf
    /// visit build nine row addresses (shifts and adds, registers spilled for them).
    std::uint32_t off_x, off_y, off_z;
#if LIBRT_ABLATION == 1
    __m128 ox, oy, oz, dx, dy, dz;  ///< measurement build: origin and direction, broadcast
#endif
};

/// Row `off` (a TriRay4 byte offset) of corner `corner` of a block.
inline __m128 load_row4(const TriangleBlock& b, std::uint32_t corner, std::uint32_t off) {
    return _mm_load_ps(
        reinterpret_cast<const float*>(reinterpret_cast<const char*>(b.p[corner]) + off));
}

/// triangle.h's prepare_watertight for a traceable ray, with its three divisions
/// (s_x = d_kx / d_kz, s_y = d_ky / d_kz, s_z = 1 / d_kz) done by one vector division:
/// IEEE division is exact per lane, so the values are the scalar ones.
inline TriRay4 prepare_triangles4(const Ray& ray) {
    constexpr std::uint32_t kRowBytes = sizeof(TriangleBlock::p[0][0]);
    const float* d = &ray.direction.x;
    const float ax = std::fabs(d[0]), ay = std::fabs(d[1]), az = std::fabs(d[2]);
    const std::uint32_t kz = (ax > ay) ? (ax > az ? 0u : 2u) : (ay > az ? 1u : 2u);
    std::uint32_t kx = kz == 2 ? 0u : kz + 1;
    std::uint32_t ky = kx == 2 ? 0u : kx + 1;
    if (d[kz] < 0.0f) std::swap(kx, ky);  // keep the winding
    const __m128 s = _mm_div_ps(_mm_setr_ps(d[kx], d[ky], 1.0f, 1.0f), _mm_set1_ps(d[kz]));
    TriRay4 r;
    r.off_x = kx * kRowBytes;
    r.off_y = ky * kRowBytes;
    r.off_z = kz * kRowBytes;
    const float* o = &ray.origin.x;
    r.o_kx = _mm_set1_ps(o[kx]);
    r.o_ky = _mm_set1_ps(o[ky]);
    r.o_kz = _mm_set1_ps(o[kz]);
    r.sx = _mm_shuffle_ps(s, s, _MM_SHUFFLE(0, 0, 0, 0));
    r.sy = _mm_shuffle_ps(s, s, _MM_SHUFFLE(1, 1, 1, 1));
    r.sz = _mm_shuffle_ps(s, s, _MM_SHUFFLE(2, 2, 2, 2));
#if LIBRT_ABLATION == 1
    // Measurement build: the watertight constants stay computed (an empty asm takes them),
    // so that only the leaf test differs.
    asm volatile("" ::"x"(r.o_kx), "x"(r.o_ky), "x"(r.o_kz), "x"(r.sx), "x"(r.sy), "x"(r.sz),
                 "r"(r.off_x), "r"(r.off_y), "r"(r.off_z));
    r.ox = _mm_set1_ps(o[0]);
    r.oy = _mm_set1_ps(o[1]);
    r.oz = _mm_set1_ps(o[2]);
    r.dx = _mm_set1_ps(d[0]);
    r.dy = _mm_set1_ps(d[1]);
    r.dz = _mm_set1_ps(d[2]);
#endif
    return r;
}

/// p q - r s per lane with the products and the difference in double, rounded to float:
/// triangle.h's exact edge function for a ray through an edge or vertex (the products of
/// two floats are exact in double). Two lanes per SSE2 double vector.
inline __m128 exact_edge4(__m128 p, __m128 q, __m128 r, __m128 s) {
    const auto pair = [](__m128 p2, __m128 q2, __m128 r2, __m128 s2) {  // lanes 0 and 1
        return _mm_cvtpd_ps(_mm_sub_pd(_mm_mul_pd(_mm_cvtps_pd(p2), _mm_cvtps_pd(q2)),
                                       _mm_mul_pd(_mm_cvtps_pd(r2), _mm_cvtps_pd(s2))));
    };
    const __m128 lo = pair(p, q, r, s);
    const __m128 hi =
        pair(_mm_movehl_ps(p, p), _mm_movehl_ps(q, q), _mm_movehl_ps(r, r), _mm_movehl_ps(s, s));
    return _mm_movelh_ps(lo, hi);
}

/// `exact` in the lanes of `mask`, `e` in the others.
inline __m128 select4(__m128 mask, __m128 exact, __m128 e) {
    return _mm_or_ps(_mm_and_ps(mask, exact), _mm_andnot_ps(mask, e));
}

#if LIBRT_ABLATION == 1
/// Measurement build: Moller-Trumbore (JGT 1997) on the precomputed edges e1 = p1 - p0,
/// e2 = p2 - p0 in a block's corners 1 and 2, in the division-free form (compares scaled by
/// |det|, one division only when a lane is hit); not watertight.
inline __m128 test_block4(const TriangleBlock& b, const TriRay4& r, __m128 t_min, __m128 t_max,
                          __m128& t, __m128& u, __m128& v) {
    const __m128 e1x = _mm_load_ps(b.p[1][0]), e1y = _mm_load_ps(b.p[1][1]),
                 e1z = _mm_load_ps(b.p[1][2]);
    const __m128 e2x = _mm_load_ps(b.p[2][0]), e2y = _mm_load_ps(b.p[2][1]),
                 e2z = _mm_load_ps(b.p[2][2]);
    // q = d x e2, det = e1 . q
    const __m128 qx = _mm_sub_ps(_mm_mul_ps(r.dy, e2z), _mm_mul_ps(r.dz, e2y));
    const __m128 qy = _mm_sub_ps(_mm_mul_ps(r.dz, e2x), _mm_mul_ps(r.dx, e2z));
    const __m128 qz = _mm_sub_ps(_mm_mul_ps(r.dx, e2y), _mm_mul_ps(r.dy, e2x));
    const __m128 det =
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(e1x, qx), _mm_mul_ps(e1y, qy)), _mm_mul_ps(e1z, qz));
    const __m128 sign = _mm_and_ps(det, _mm_set1_ps(-0.0f));
    const __m128 abs_det = _mm_xor_ps(det, sign);
    // s = o - p0; u det = s . q; w = s x e1; v det = d . w; t det = e2 . w
    const __m128 sx = _mm_sub_ps(r.ox, _mm_load_ps(b.p[0][0]));
    const __m128 sy = _mm_sub_ps(r.oy, _mm_load_ps(b.p[0][1]));
    const __m128 sz = _mm_sub_ps(r.oz, _mm_load_ps(b.p[0][2]));
    const __m128 us = _mm_xor_ps(
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(sx, qx), _mm_mul_ps(sy, qy)), _mm_mul_ps(sz, qz)), sign);
    const __m128 wx = _mm_sub_ps(_mm_mul_ps(sy, e1z), _mm_mul_ps(sz, e1y));
    const __m128 wy = _mm_sub_ps(_mm_mul_ps(sz, e1x), _mm_mul_ps(sx, e1z));
    const __m128 wz = _mm_sub_ps(_mm_mul_ps(sx, e1y), _mm_mul_ps(sy, e1x));
    const __m128 vs = _mm_xor_ps(
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(r.dx, wx), _mm_mul_ps(r.dy, wy)), _mm_mul_ps(r.dz, wz)),
        sign);
    const __m128 zero = _mm_setzero_ps();
    __m128 ok =
        _mm_and_ps(_mm_and_ps(_mm_cmpneq_ps(det, zero), _mm_cmpge_ps(us, zero)),
                   _mm_and_ps(_mm_cmpge_ps(vs, zero), _mm_cmple_ps(_mm_add_ps(us, vs), abs_det)));
    if (_mm_movemask_ps(ok) == 0) return ok;
    const __m128 ts = _mm_xor_ps(
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(e2x, wx), _mm_mul_ps(e2y, wy)), _mm_mul_ps(e2z, wz)),
        sign);
    ok = _mm_and_ps(ok, _mm_and_ps(_mm_cmpgt_ps(ts, _mm_mul_ps(abs_det, t_min)),
                                   _mm_cmplt_ps(ts, _mm_mul_ps(abs_det, t_max))));
    if (_mm_movemask_ps(ok) == 0) return ok;
    const __m128 inv_det = _mm_div_ps(_mm_set1_ps(1.0f), abs_det);
    t = _mm_mul_ps(ts, inv_det);
    u = _mm_mul_ps(us, inv_det);
    v = _mm_mul_ps(vs, inv_det);
    return ok;
}
#else
/// Watertight ray-triangle test (Woop, Benthin and Wald, JCGT 2013) of a block's four
/// triangles. Returns the lanes hit with t in (t_min, t_max) (all bits set in those lanes),
/// and their t, u, v.
inline __m128 test_block4(const TriangleBlock& b, const TriRay4& r, __m128 t_min, __m128 t_max,
                          __m128& t, __m128& u, __m128& v) {
    // Corners relative to the origin; z along the permuted axis kz...
    const __m128 az = _mm_sub_ps(load_row4(b, 0, r.off_z), r.o_kz);
    const __m128 bz = _mm_sub_ps(load_row4(b, 1, r.off_z), r.o_kz);
    const __m128 cz = _mm_sub_ps(load_row4(b, 2, r.off_z), r.o_kz);
    // ...and x, y sheared so the ray runs along +z: x' = x - s_x z, y' = y - s_y z.
    const __m128 ax =
        _mm_sub_ps(_mm_sub_ps(load_row4(b, 0, r.off_x), r.o_kx), _mm_mul_ps(r.sx, az));
    const __m128 ay =
        _mm_sub_ps(_mm_sub_ps(load_row4(b, 0, r.off_y), r.o_ky), _mm_mul_ps(r.sy, az));
    const __m128 bx =
        _mm_sub_ps(_mm_sub_ps(load_row4(b, 1, r.off_x), r.o_kx), _mm_mul_ps(r.sx, bz));
    const __m128 by =
        _mm_sub_ps(_mm_sub_ps(load_row4(b, 1, r.off_y), r.o_ky), _mm_mul_ps(r.sy, bz));
    const __m128 cx =
        _mm_sub_ps(_mm_sub_ps(load_row4(b, 2, r.off_x), r.o_kx), _mm_mul_ps(r.sx, cz));
    const __m128 cy =
        _mm_sub_ps(_mm_sub_ps(load_row4(b, 2, r.off_y), r.o_ky), _mm_mul_ps(r.sy, cz));

    // 2D edge functions (scaled barycentrics): e0 = cx by - cy bx, e1 = ax cy - ay cx, e2 = bx ay -
    // by ax.
    __m128 e0 = _mm_sub_ps(_mm_mul_ps(cx, by), _mm_mul_ps(cy, bx));
    __m128 e1 = _mm_sub_ps(_mm_mul_ps(ax, cy), _mm_mul_ps(ay, cx));
    __m128 e2 = _mm_sub_ps(_mm_mul_ps(bx, ay), _mm_mul_ps(by, ax));
    const __m128 zero = _mm_setzero_ps();
    const __m128 on_edge = _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(e0, zero), _mm_cmpeq_ps(e1, zero)),
                                     _mm_cmpeq_ps(e2, zero));
    // Lanes rejected before t (all bits set): the three signs disagree, or det = 0.
    __m128 rejected;
    if (_mm_movemask_ps(on_edge) != 0) [[unlikely]] {
        // Inline and in registers: a call taking the edges by reference kept them in
        // memory on every block test.
        e0 = select4(on_edge, exact_edge4(cx, by, cy, bx), e0);
        e1 = select4(on_edge, exact_edge4(ax, cy, ay, cx), e1);
        e2 = select4(on_edge, exact_edge4(bx, ay, by, ax), e2);
        // Inside when the three signs agree (either winding), a zero agreeing with both.
        const __m128 any_neg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(e0, zero), _mm_cmplt_ps(e1, zero)),
                                         _mm_cmplt_ps(e2, zero));
        const __m128 any_pos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(e0, zero), _mm_cmpgt_ps(e1, zero)),
                                         _mm_cmpgt_ps(e2, zero));
        const __m128 det0 = _mm_cmpeq_ps(_mm_add_ps(_mm_add_ps(e0, e1), e2), zero);
        rejected = _mm_or_ps(_mm_and_ps(any_neg, any_pos), det0);
    } else {
        // No edge is zero, so an edge is negative exactly when its sign bit is set (NaN
        // lanes aside, which their NaN t rejects below): the signs disagree where the or
        // of the three sign bits is set and their and is clear. The sum of three nonzero
        // values of one sign is not zero, so det = 0 needs no test here.
        const __m128 mixed =
            _mm_andnot_ps(_mm_and_ps(_mm_and_ps(e0, e1), e2), _mm_or_ps(_mm_or_ps(e0, e1), e2));
        rejected = _mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(mixed), 31));
    }
    // (No early exit when every lane is rejected: whether any lane is inside is a coin toss,
    // and the division is cheaper than the mispredicted branch, also for any hit.)
    const __m128 det = _mm_add_ps(_mm_add_ps(e0, e1), e2);

    // t = s_z (e0 az + e1 bz + e2 cz) / det, barycentrics u = e1 / det, v = e2 / det.
    const __m128 t_scaled = _mm_mul_ps(
        r.sz, _mm_add_ps(_mm_add_ps(_mm_mul_ps(e0, az), _mm_mul_ps(e1, bz)), _mm_mul_ps(e2, cz)));
    const __m128 inv_det = _mm_div_ps(_mm_set1_ps(1.0f), det);
    t = _mm_mul_ps(t_scaled, inv_det);
    const __m128 ok =
        _mm_andnot_ps(rejected, _mm_and_ps(_mm_cmpgt_ps(t, t_min), _mm_cmplt_ps(t, t_max)));
    u = _mm_mul_ps(e1, inv_det);
    v = _mm_mul_ps(e2, inv_det);
    return ok;
}
#endif

/// The triangle half of a WideKernel policy (see wide_traversal.h): four triangles a test.
struct Block4Triangles {
    using TriRay = TriRay4;

    static TriRay prepare_triangles(const Ray& ray) { return prepare_triangles4(ray); }

    static bool intersect_block(const TriangleBlock& block, const TriRay& r, float t_min,
                                float& t_max, std::uint32_t& lane, float& u, float& v) {
        __m128 t4, u4, v4;
        const __m128 hit =
            test_block4(block, r, _mm_set1_ps(t_min), _mm_set1_ps(t_max), t4, u4, v4);
        if (_mm_movemask_ps(hit) == 0) return false;
        // The nearest lane without branches: the minimum of the hit lanes' t (misses count as
        // +inf), then the lowest lane holding it, as the scalar loop keeps the first of equals.
        const __m128 tt = _mm_or_ps(_mm_and_ps(hit, t4), _mm_andnot_ps(hit, _mm_set1_ps(INFINITY)));
        __m128 m = _mm_min_ps(tt, _mm_shuffle_ps(tt, tt, _MM_SHUFFLE(2, 3, 0, 1)));
        m = _mm_min_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 3, 2)));
        const int nearest = _mm_movemask_ps(_mm_and_ps(hit, _mm_cmpeq_ps(tt, m)));
        const auto k = static_cast<std::uint32_t>(std::countr_zero(static_cast<unsigned>(nearest)));
        alignas(16) float ts[4], us[4], vs[4];
        _mm_store_ps(ts, t4);
        _mm_store_ps(us, u4);
        _mm_store_ps(vs, v4);
        t_max = ts[k];
        lane = k;
        u = us[k];
        v = vs[k];
        return true;
    }

    static bool occluded_block(const TriangleBlock& block, const TriRay& r, float t_min,
                               float t_max) {
        __m128 t4, u4, v4;
        return _mm_movemask_ps(
                   test_block4(block, r, _mm_set1_ps(t_min), _mm_set1_ps(t_max), t4, u4, v4)) != 0;
    }
};

}  // namespace librt::detail
