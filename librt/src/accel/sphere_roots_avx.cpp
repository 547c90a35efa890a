// The AVX sphere-root kernel (sphere_roots.h): four spheres per instruction. The same
// operations in the same order as the SSE2 kernel in sphere_roots.cpp, lane by lane; only
// this file is compiled for AVX (a target pragma, as wide_avx2.cpp does), and it runs only
// when simd_path_supported() says the CPU has AVX2 (so AVX).
// Why not one template for both widths: a target applies to the functions defined under
// it, so the AVX entry point must be defined here under its own pragma.

#include "accel/sphere_roots.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx")
#endif

namespace librt::detail {

std::uint32_t sphere_roots_avx(const SphereLanes& spheres, const DoubleRay& ray, double t_min,
                               double t_max, double* roots) {
    const __m256d ox = _mm256_set1_pd(ray.origin.x), oy = _mm256_set1_pd(ray.origin.y),
                  oz = _mm256_set1_pd(ray.origin.z);
    const __m256d dx = _mm256_set1_pd(ray.direction.x), dy = _mm256_set1_pd(ray.direction.y),
                  dz = _mm256_set1_pd(ray.direction.z);
    const __m256d a = _mm256_set1_pd(ray.a), inv_a = _mm256_set1_pd(ray.inv_a);
    const __m256d lo = _mm256_set1_pd(t_min), hi = _mm256_set1_pd(t_max);
    const __m256d zero = _mm256_setzero_pd(), sign = _mm256_set1_pd(-0.0);
    const __m256d none = _mm256_set1_pd(__builtin_nan(""));
    const __m256d inf = _mm256_set1_pd(__builtin_inf());
    std::uint32_t mask = 0;
    for (std::uint32_t i = 0; i < spheres.count; i += 4) {
        const __m256d r2 = _mm256_loadu_pd(spheres.r2 + i);
        // oc = o - c; b = oc . d; c = oc . oc - r^2 (glm's dot: (x + y) + z).
        const __m256d ocx = _mm256_sub_pd(ox, _mm256_loadu_pd(spheres.cx + i));
        const __m256d ocy = _mm256_sub_pd(oy, _mm256_loadu_pd(spheres.cy + i));
        const __m256d ocz = _mm256_sub_pd(oz, _mm256_loadu_pd(spheres.cz + i));
        const __m256d b = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(ocx, dx), _mm256_mul_pd(ocy, dy)), _mm256_mul_pd(ocz, dz));
        const __m256d c = _mm256_sub_pd(
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ocx, ocx), _mm256_mul_pd(ocy, ocy)),
                          _mm256_mul_pd(ocz, ocz)),
            r2);
        // Outside and moving away: no root (the scalar test's early return).
        const __m256d away =
            _mm256_and_pd(_mm256_cmp_pd(b, zero, _CMP_GE_OQ), _mm256_cmp_pd(c, zero, _CMP_GT_OQ));
        // Half-chord^2 = r^2 - |oc - (b / a) d|^2.
        const __m256d s = _mm256_mul_pd(b, inv_a);
        const __m256d clx = _mm256_sub_pd(ocx, _mm256_mul_pd(s, dx));
        const __m256d cly = _mm256_sub_pd(ocy, _mm256_mul_pd(s, dy));
        const __m256d clz = _mm256_sub_pd(ocz, _mm256_mul_pd(s, dz));
        const __m256d hc2 = _mm256_sub_pd(
            r2, _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(clx, clx), _mm256_mul_pd(cly, cly)),
                              _mm256_mul_pd(clz, clz)));
        const __m256d meets = _mm256_andnot_pd(away, _mm256_cmp_pd(hc2, zero, _CMP_GE_OQ));
        // q = -(b + copysign(sqrt(hc2 a), b)); roots q / a and c / q (q / a when q = 0).
        const __m256d root = _mm256_sqrt_pd(_mm256_mul_pd(hc2, a));
        const __m256d signed_root =
            _mm256_or_pd(_mm256_andnot_pd(sign, root), _mm256_and_pd(sign, b));
        const __m256d q = _mm256_xor_pd(_mm256_add_pd(b, signed_root), sign);
        const __m256d t_a = _mm256_mul_pd(q, inv_a);
        const __m256d q_nonzero = _mm256_cmp_pd(q, zero, _CMP_NEQ_UQ);
        const __m256d t_b = _mm256_or_pd(_mm256_and_pd(q_nonzero, _mm256_div_pd(c, q)),
                                         _mm256_andnot_pd(q_nonzero, t_a));
        // std::min(t_a, t_b) is t_b < t_a ? t_b : t_a, which minpd(t_b, t_a) is; max likewise.
        const __m256d near = _mm256_min_pd(t_b, t_a), far = _mm256_max_pd(t_b, t_a);
        const __m256d near_in =
            _mm256_and_pd(_mm256_cmp_pd(near, lo, _CMP_GT_OQ), _mm256_cmp_pd(near, hi, _CMP_LT_OQ));
        const __m256d far_in =
            _mm256_and_pd(_mm256_cmp_pd(far, lo, _CMP_GT_OQ), _mm256_cmp_pd(far, hi, _CMP_LT_OQ));
        const __m256d t = _mm256_or_pd(
            _mm256_and_pd(near_in, near),
            _mm256_andnot_pd(
                near_in, _mm256_or_pd(_mm256_and_pd(far_in, far), _mm256_andnot_pd(far_in, none))));
        const __m256d result = _mm256_or_pd(_mm256_and_pd(meets, t), _mm256_andnot_pd(meets, none));
        // A hit is a root >= 0 (TopLevel's test); the others become +inf.
        const __m256d hit = _mm256_cmp_pd(result, zero, _CMP_GE_OQ);
        _mm256_storeu_pd(roots + i, _mm256_blendv_pd(inf, result, hit));
        mask |= std::uint32_t(_mm256_movemask_pd(hit)) << i;
    }
    // Lanes past count (a count not a multiple of 4) hold the empty sphere: their bit is never set.
    return mask;
}
}  // namespace librt::detail

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif
