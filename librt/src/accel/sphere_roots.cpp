// The SSE2 sphere-root kernel and the choice of kernel (sphere_roots.h); AVX and AVX-512 are
// in sphere_roots_avx.cpp and sphere_roots_avx512.cpp. All three run sphere_roots_kernel.h,
// each through its own lane policy.

#include "accel/sphere_roots.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include "accel/sphere_roots_kernel.h"

#include <immintrin.h>
#endif

namespace librt::detail {

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
namespace {

/// The SphereLaneOps policy of SSE2: two lanes, masks as all-ones or all-zero lanes.
struct Sse2Lanes {
    using Vec = __m128d;
    using Mask = __m128d;
    static constexpr std::uint32_t kWidth = 2;
    static Vec set1(double x) { return _mm_set1_pd(x); }
    static Vec load(const double* p) { return _mm_loadu_pd(p); }
    static void store(double* p, Vec v) { _mm_storeu_pd(p, v); }
    static Vec add(Vec a, Vec b) { return _mm_add_pd(a, b); }
    static Vec sub(Vec a, Vec b) { return _mm_sub_pd(a, b); }
    static Vec mul(Vec a, Vec b) { return _mm_mul_pd(a, b); }
    static Vec div(Vec a, Vec b) { return _mm_div_pd(a, b); }
    static Vec sqrt(Vec a) { return _mm_sqrt_pd(a); }
    static Vec min(Vec a, Vec b) { return _mm_min_pd(a, b); }
    static Vec max(Vec a, Vec b) { return _mm_max_pd(a, b); }
    static Mask ge(Vec a, Vec b) { return _mm_cmpge_pd(a, b); }
    static Mask gt(Vec a, Vec b) { return _mm_cmpgt_pd(a, b); }
    static Mask lt(Vec a, Vec b) { return _mm_cmplt_pd(a, b); }
    static Mask ne(Vec a, Vec b) { return _mm_cmpneq_pd(a, b); }
    static Mask both(Mask m, Mask n) { return _mm_and_pd(m, n); }
    static Mask but_not(Mask m, Mask n) { return _mm_andnot_pd(m, n); }
    static Vec select(Mask m, Vec a, Vec b) {
        return _mm_or_pd(_mm_and_pd(m, a), _mm_andnot_pd(m, b));
    }
    static Vec copysign(Vec a, Vec b) {
        const Vec sign = _mm_set1_pd(-0.0);
        return _mm_or_pd(_mm_andnot_pd(sign, a), _mm_and_pd(sign, b));
    }
    static Vec negate(Vec a) { return _mm_xor_pd(a, _mm_set1_pd(-0.0)); }
    static std::uint32_t bits(Mask m) { return std::uint32_t(_mm_movemask_pd(m)); }
};

}  // namespace

std::uint32_t sphere_roots_sse2(const SphereLanes& spheres, const DoubleRay& ray, double t_min,
                                double t_max, double* roots) {
    return sphere_roots_lanes<Sse2Lanes>(spheres, ray, t_min, t_max, roots);
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
