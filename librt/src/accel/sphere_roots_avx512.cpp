// The AVX-512 sphere-root kernel (sphere_roots.h): eight spheres per instruction, the lane
// masks in mask registers, through sphere_roots_kernel.h with the lane policy below. Only
// this file is compiled for AVX-512 F (a target pragma, as wide_avx512.cpp does), and it runs
// only when simd_path_supported() says the CPU has it; the policy, the kernel template and
// the entry point are declared under the pragma, as in sphere_roots_avx.cpp.

#include "accel/sphere_roots.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

#include <concepts>
#include <cstdint>

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

// The kernel template is declared here, under the target, so that its instantiation with this
// file's policy is compiled for it (its own includes came first, above, as baseline code).
#include "accel/sphere_roots_kernel.h"

namespace librt::detail {
namespace {

/// The SphereLaneOps policy of AVX-512 F: eight lanes, masks as the bits of a mask register.
struct Avx512Lanes {
    using Vec = __m512d;
    using Mask = __mmask8;
    static constexpr std::uint32_t kWidth = 8;
    static Vec set1(double x) { return _mm512_set1_pd(x); }
    static Vec load(const double* p) { return _mm512_loadu_pd(p); }
    static void store(double* p, Vec v) { _mm512_storeu_pd(p, v); }
    static Vec add(Vec a, Vec b) { return _mm512_add_pd(a, b); }
    static Vec sub(Vec a, Vec b) { return _mm512_sub_pd(a, b); }
    static Vec mul(Vec a, Vec b) { return _mm512_mul_pd(a, b); }
    static Vec div(Vec a, Vec b) { return _mm512_div_pd(a, b); }
    static Vec sqrt(Vec a) { return _mm512_sqrt_pd(a); }
    static Vec min(Vec a, Vec b) { return _mm512_min_pd(a, b); }
    static Vec max(Vec a, Vec b) { return _mm512_max_pd(a, b); }
    static Mask ge(Vec a, Vec b) { return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ); }
    static Mask gt(Vec a, Vec b) { return _mm512_cmp_pd_mask(a, b, _CMP_GT_OQ); }
    static Mask lt(Vec a, Vec b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
    static Mask ne(Vec a, Vec b) { return _mm512_cmp_pd_mask(a, b, _CMP_NEQ_UQ); }
    static Mask both(Mask m, Mask n) { return Mask(m & n); }
    static Mask but_not(Mask m, Mask n) { return Mask(Mask(~m) & n); }
    static Vec select(Mask m, Vec a, Vec b) { return _mm512_mask_blend_pd(m, b, a); }
    // On the bits, as integers: AVX-512 F has no floating-point and, or and xor (DQ has).
    static Vec copysign(Vec a, Vec b) {
        const __m512i sign = _mm512_set1_epi64(std::int64_t(0x8000000000000000ULL));
        return _mm512_castsi512_pd(
            _mm512_or_si512(_mm512_andnot_si512(sign, _mm512_castpd_si512(a)),
                            _mm512_and_si512(sign, _mm512_castpd_si512(b))));
    }
    static Vec negate(Vec a) {
        const __m512i sign = _mm512_set1_epi64(std::int64_t(0x8000000000000000ULL));
        return _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(a), sign));
    }
    static std::uint32_t bits(Mask m) { return std::uint32_t(m); }
};

}  // namespace

std::uint32_t sphere_roots_avx512(const SphereLanes& spheres, const DoubleRay& ray, double t_min,
                                  double t_max, double* roots) {
    return sphere_roots_lanes<Avx512Lanes>(spheres, ray, t_min, t_max, roots);
}

}  // namespace librt::detail

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC diagnostic pop
#pragma GCC pop_options
#endif
#endif
