// The AVX sphere-root kernel (sphere_roots.h): four spheres per instruction, through
// sphere_roots_kernel.h with the lane policy below. Only this file is compiled for AVX (a
// target pragma, as wide_avx2.cpp does), and it runs only when simd_path_supported() says
// the CPU has AVX2 (so AVX). The policy, the kernel template and the entry point are declared
// under the pragma, because a target applies to the functions declared under it.

#include "accel/sphere_roots.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

#include <concepts>
#include <cstdint>

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx")
#endif

// The kernel template is declared here, under the target, so that its instantiation with this
// file's policy is compiled for it (its own includes came first, above, as baseline code).
#include "accel/sphere_roots_kernel.h"

namespace librt::detail {
namespace {

/// The SphereLaneOps policy of AVX: four lanes, masks as all-ones or all-zero lanes.
struct AvxLanes {
    using Vec = __m256d;
    using Mask = __m256d;
    static constexpr std::uint32_t kWidth = 4;
    static Vec set1(double x) { return _mm256_set1_pd(x); }
    static Vec load(const double* p) { return _mm256_loadu_pd(p); }
    static void store(double* p, Vec v) { _mm256_storeu_pd(p, v); }
    static Vec add(Vec a, Vec b) { return _mm256_add_pd(a, b); }
    static Vec sub(Vec a, Vec b) { return _mm256_sub_pd(a, b); }
    static Vec mul(Vec a, Vec b) { return _mm256_mul_pd(a, b); }
    static Vec div(Vec a, Vec b) { return _mm256_div_pd(a, b); }
    static Vec sqrt(Vec a) { return _mm256_sqrt_pd(a); }
    static Vec min(Vec a, Vec b) { return _mm256_min_pd(a, b); }
    static Vec max(Vec a, Vec b) { return _mm256_max_pd(a, b); }
    static Mask ge(Vec a, Vec b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
    static Mask gt(Vec a, Vec b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
    static Mask lt(Vec a, Vec b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
    static Mask ne(Vec a, Vec b) { return _mm256_cmp_pd(a, b, _CMP_NEQ_UQ); }
    static Mask both(Mask m, Mask n) { return _mm256_and_pd(m, n); }
    static Mask but_not(Mask m, Mask n) { return _mm256_andnot_pd(m, n); }
    // By and / or, not blendv: g++ 12 folds blendv into a per-lane select that, with AVX's
    // 256-bit integer compares missing, it lowers to a branch per lane.
    static Vec select(Mask m, Vec a, Vec b) {
        return _mm256_or_pd(_mm256_and_pd(m, a), _mm256_andnot_pd(m, b));
    }
    static Vec copysign(Vec a, Vec b) {
        const Vec sign = _mm256_set1_pd(-0.0);
        return _mm256_or_pd(_mm256_andnot_pd(sign, a), _mm256_and_pd(sign, b));
    }
    static Vec negate(Vec a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
    static std::uint32_t bits(Mask m) { return std::uint32_t(_mm256_movemask_pd(m)); }
};

}  // namespace

std::uint32_t sphere_roots_avx(const SphereLanes& spheres, const DoubleRay& ray, double t_min,
                               double t_max, double* roots) {
    return sphere_roots_lanes<AvxLanes>(spheres, ray, t_min, t_max, roots);
}

}  // namespace librt::detail

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif
