// The SSE2 sphere-root kernel and the choice of kernel (sphere_roots.h); AVX and AVX-512 are
// in sphere_roots_avx.cpp and sphere_roots_avx512.cpp.

#include "accel/sphere_roots.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif

namespace librt::detail {

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
std::uint32_t sphere_roots_sse2(const SphereLanes& spheres, const DoubleRay& ray, double t_min,
                                double t_max, double* roots) {
    const __m128d ox = _mm_set1_pd(ray.origin.x), oy = _mm_set1_pd(ray.origin.y),
                  oz = _mm_set1_pd(ray.origin.z);
    const __m128d dx = _mm_set1_pd(ray.direction.x), dy = _mm_set1_pd(ray.direction.y),
                  dz = _mm_set1_pd(ray.direction.z);
    const __m128d a = _mm_set1_pd(ray.a), inv_a = _mm_set1_pd(ray.inv_a);
    const __m128d lo = _mm_set1_pd(t_min), hi = _mm_set1_pd(t_max);
    const __m128d zero = _mm_setzero_pd(), sign = _mm_set1_pd(-0.0);
    const __m128d none = _mm_set1_pd(__builtin_nan(""));
    const __m128d inf = _mm_set1_pd(__builtin_inf());
    std::uint32_t mask = 0;
    for (std::uint32_t i = 0; i < spheres.count; i += 2) {
        const __m128d r2 = _mm_loadu_pd(spheres.r2 + i);
        // oc = o - c; b = oc . d; c = oc . oc - r^2 (glm's dot: (x + y) + z).
        const __m128d ocx = _mm_sub_pd(ox, _mm_loadu_pd(spheres.cx + i));
        const __m128d ocy = _mm_sub_pd(oy, _mm_loadu_pd(spheres.cy + i));
        const __m128d ocz = _mm_sub_pd(oz, _mm_loadu_pd(spheres.cz + i));
        const __m128d b =
            _mm_add_pd(_mm_add_pd(_mm_mul_pd(ocx, dx), _mm_mul_pd(ocy, dy)), _mm_mul_pd(ocz, dz));
        const __m128d c =
            _mm_sub_pd(_mm_add_pd(_mm_add_pd(_mm_mul_pd(ocx, ocx), _mm_mul_pd(ocy, ocy)),
                                  _mm_mul_pd(ocz, ocz)),
                       r2);
        // Outside and moving away: no root (the scalar test's early return).
        const __m128d away = _mm_and_pd(_mm_cmpge_pd(b, zero), _mm_cmpgt_pd(c, zero));
        // Half-chord^2 = r^2 - |oc - (b / a) d|^2.
        const __m128d s = _mm_mul_pd(b, inv_a);
        const __m128d clx = _mm_sub_pd(ocx, _mm_mul_pd(s, dx));
        const __m128d cly = _mm_sub_pd(ocy, _mm_mul_pd(s, dy));
        const __m128d clz = _mm_sub_pd(ocz, _mm_mul_pd(s, dz));
        const __m128d hc2 =
            _mm_sub_pd(r2, _mm_add_pd(_mm_add_pd(_mm_mul_pd(clx, clx), _mm_mul_pd(cly, cly)),
                                      _mm_mul_pd(clz, clz)));
        const __m128d meets = _mm_andnot_pd(away, _mm_cmpge_pd(hc2, zero));
        // q = -(b + copysign(sqrt(hc2 a), b)); roots q / a and c / q (q / a when q = 0).
        const __m128d root = _mm_sqrt_pd(_mm_mul_pd(hc2, a));
        const __m128d signed_root = _mm_or_pd(_mm_andnot_pd(sign, root), _mm_and_pd(sign, b));
        const __m128d q = _mm_xor_pd(_mm_add_pd(b, signed_root), sign);
        const __m128d t_a = _mm_mul_pd(q, inv_a);
        const __m128d q_nonzero = _mm_cmpneq_pd(q, zero);
        const __m128d t_b =
            _mm_or_pd(_mm_and_pd(q_nonzero, _mm_div_pd(c, q)), _mm_andnot_pd(q_nonzero, t_a));
        // std::min(t_a, t_b) is t_b < t_a ? t_b : t_a, which minpd(t_b, t_a) is; max likewise.
        const __m128d near = _mm_min_pd(t_b, t_a), far = _mm_max_pd(t_b, t_a);
        const __m128d near_in = _mm_and_pd(_mm_cmpgt_pd(near, lo), _mm_cmplt_pd(near, hi));
        const __m128d far_in = _mm_and_pd(_mm_cmpgt_pd(far, lo), _mm_cmplt_pd(far, hi));
        const __m128d t = _mm_or_pd(_mm_and_pd(near_in, near),
                                    _mm_andnot_pd(near_in, _mm_or_pd(_mm_and_pd(far_in, far),
                                                                     _mm_andnot_pd(far_in, none))));
        const __m128d result = _mm_or_pd(_mm_and_pd(meets, t), _mm_andnot_pd(meets, none));
        // A hit is a root >= 0 (TopLevel's test); the others become +inf.
        const __m128d hit = _mm_cmpge_pd(result, zero);
        _mm_storeu_pd(roots + i, _mm_or_pd(_mm_and_pd(hit, result), _mm_andnot_pd(hit, inf)));
        mask |= std::uint32_t(_mm_movemask_pd(hit)) << i;
    }
    // Lanes past count (an odd count) hold the empty sphere: their bit is never set.
    return mask;
}
#endif

SphereRootsFn sphere_roots_for(SimdPath path) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    switch (path) {
        case SimdPath::Scalar:
            return nullptr;
        case SimdPath::Sse:
            return &sphere_roots_sse2;
        case SimdPath::Avx2:
            return &sphere_roots_avx;
        case SimdPath::Avx512:
            return &sphere_roots_avx512;
    }
#else
    (void)path;
#endif
    return nullptr;
}

}  // namespace librt::detail
