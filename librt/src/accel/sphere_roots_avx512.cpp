// The AVX-512 sphere-root kernel (sphere_roots.h): eight spheres per instruction, with the
// lane masks in mask registers. The same operations in the same order as the SSE2 kernel in
// sphere_roots.cpp, lane by lane; only this file is compiled for AVX-512 F (a target pragma,
// as wide_avx512.cpp does), and it runs only when simd_path_supported() says the CPU has it.

#include "accel/sphere_roots.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx512f"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f")
// g++ 12's own avx512fintrin.h passes _mm512_undefined_pd() as the unused source of its
// unmasked sqrt, andnot, min and max, and then warns about that value it made.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace librt::detail {

std::uint32_t sphere_roots_avx512(const SphereLanes& spheres, const DoubleRay& ray, double t_min,
                                  double t_max, double* roots) {
    const __m512d ox = _mm512_set1_pd(ray.origin.x), oy = _mm512_set1_pd(ray.origin.y),
                  oz = _mm512_set1_pd(ray.origin.z);
    const __m512d dx = _mm512_set1_pd(ray.direction.x), dy = _mm512_set1_pd(ray.direction.y),
                  dz = _mm512_set1_pd(ray.direction.z);
    const __m512d a = _mm512_set1_pd(ray.a), inv_a = _mm512_set1_pd(ray.inv_a);
    const __m512d lo = _mm512_set1_pd(t_min), hi = _mm512_set1_pd(t_max);
    const __m512d zero = _mm512_setzero_pd();
    const __m512i sign = _mm512_set1_epi64(std::int64_t(0x8000000000000000ULL));
    const __m512d none = _mm512_set1_pd(__builtin_nan(""));
    const __m512d inf = _mm512_set1_pd(__builtin_inf());
    std::uint32_t mask = 0;
    for (std::uint32_t i = 0; i < spheres.count; i += 8) {
        const __m512d r2 = _mm512_loadu_pd(spheres.r2 + i);
        // oc = o - c; b = oc . d; c = oc . oc - r^2 (glm's dot: (x + y) + z).
        const __m512d ocx = _mm512_sub_pd(ox, _mm512_loadu_pd(spheres.cx + i));
        const __m512d ocy = _mm512_sub_pd(oy, _mm512_loadu_pd(spheres.cy + i));
        const __m512d ocz = _mm512_sub_pd(oz, _mm512_loadu_pd(spheres.cz + i));
        const __m512d b = _mm512_add_pd(
            _mm512_add_pd(_mm512_mul_pd(ocx, dx), _mm512_mul_pd(ocy, dy)), _mm512_mul_pd(ocz, dz));
        const __m512d c = _mm512_sub_pd(
            _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(ocx, ocx), _mm512_mul_pd(ocy, ocy)),
                          _mm512_mul_pd(ocz, ocz)),
            r2);
        // Outside and moving away: no root (the scalar test's early return).
        const __mmask8 away =
            _mm512_cmp_pd_mask(b, zero, _CMP_GE_OQ) & _mm512_cmp_pd_mask(c, zero, _CMP_GT_OQ);
        // Half-chord^2 = r^2 - |oc - (b / a) d|^2.
        const __m512d s = _mm512_mul_pd(b, inv_a);
        const __m512d clx = _mm512_sub_pd(ocx, _mm512_mul_pd(s, dx));
        const __m512d cly = _mm512_sub_pd(ocy, _mm512_mul_pd(s, dy));
        const __m512d clz = _mm512_sub_pd(ocz, _mm512_mul_pd(s, dz));
        const __m512d hc2 = _mm512_sub_pd(
            r2, _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(clx, clx), _mm512_mul_pd(cly, cly)),
                              _mm512_mul_pd(clz, clz)));
        const __mmask8 meets = __mmask8(~away) & _mm512_cmp_pd_mask(hc2, zero, _CMP_GE_OQ);
        // q = -(b + copysign(sqrt(hc2 a), b)); roots q / a and c / q (q / a when q = 0).
        const __m512i root = _mm512_castpd_si512(_mm512_sqrt_pd(_mm512_mul_pd(hc2, a)));
        const __m512i b_bits = _mm512_castpd_si512(b);
        const __m512d signed_root = _mm512_castsi512_pd(
            _mm512_or_si512(_mm512_andnot_si512(sign, root), _mm512_and_si512(sign, b_bits)));
        const __m512d q = _mm512_castsi512_pd(
            _mm512_xor_si512(_mm512_castpd_si512(_mm512_add_pd(b, signed_root)), sign));
        const __m512d t_a = _mm512_mul_pd(q, inv_a);
        const __mmask8 q_nonzero = _mm512_cmp_pd_mask(q, zero, _CMP_NEQ_UQ);
        const __m512d t_b = _mm512_mask_blend_pd(q_nonzero, t_a, _mm512_div_pd(c, q));
        // std::min(t_a, t_b) is t_b < t_a ? t_b : t_a, which minpd(t_b, t_a) is; max likewise.
        const __m512d near = _mm512_min_pd(t_b, t_a), far = _mm512_max_pd(t_b, t_a);
        const __mmask8 near_in =
            _mm512_cmp_pd_mask(near, lo, _CMP_GT_OQ) & _mm512_cmp_pd_mask(near, hi, _CMP_LT_OQ);
        const __mmask8 far_in =
            _mm512_cmp_pd_mask(far, lo, _CMP_GT_OQ) & _mm512_cmp_pd_mask(far, hi, _CMP_LT_OQ);
        const __m512d t =
            _mm512_mask_blend_pd(near_in, _mm512_mask_blend_pd(far_in, none, far), near);
        const __m512d result = _mm512_mask_blend_pd(meets, none, t);
        // A hit is a root >= 0 (TopLevel's test); the others become +inf.
        const __mmask8 hit = _mm512_cmp_pd_mask(result, zero, _CMP_GE_OQ);
        _mm512_storeu_pd(roots + i, _mm512_mask_blend_pd(hit, inf, result));
        mask |= std::uint32_t(hit) << i;
    }
    // Lanes past count (a count not a multiple of 8) hold the empty sphere: their bit is never set.
    return mask;
}
}  // namespace librt::detail

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC diagnostic pop
#pragma GCC pop_options
#endif
#endif
