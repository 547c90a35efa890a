#pragma once

// Private: bbox.h's conservative slab test, in a fused form (FMA), on the eight children of a
// wide node in one AVX test, the node half of the AVX2 and AVX-512 kernels. Compiled for
// AVX2 and FMA (a target pragma around this header's own code, not a -m flag on a file, so
// nothing leaks into baseline code); it runs only when simd_path_supported() says the CPU
// has them.

#include "slab4.h"
#include "wide_bvh.h"

#include <librt/geometry/bbox.h>
#include <librt/geometry/ray.h>

#include <immintrin.h>

#include <cmath>
#include <cstdint>

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,fma,popcnt,bmi"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,fma,popcnt,bmi")
#endif

namespace librt::detail {

/// Per-ray constants of slab_test8, for the fused form of bbox.h's slab test: per axis the
/// safe inverse direction and origin x inverse, the latter rounded outwards twice (one for
/// the near planes, one for the far), and the bounds rows the ray enters and leaves through
/// (see SlabRay4).
struct SlabRay8 {
    __m256 inv[3];          ///< safe_inverse(direction)[a] in every lane
    __m256 near_oi[3];      ///< a float >= origin[a] x inv[a] (exact product), every lane
    __m256 far_oi[3];       ///< a float <= origin[a] x inv[a] (exact product), every lane
    std::uint32_t near[3];  ///< row of the plane the ray enters through along each axis
    std::uint32_t far[3];   ///< row of the plane it leaves through
};

/// Largest origin coordinate the fused slab test takes: with |inverse| <= 1e30 (safe_inverse)
/// origin x inverse then stays below 2^126, so the two rounded products are finite. A ray
/// from farther out takes another kernel (slab8_in_range).
inline constexpr float kSlab8MaxOrigin = 0x1p26f;

/// True when prepare_slab8's constants are finite for this ray (every coordinate of its
/// origin below kSlab8MaxOrigin in magnitude), i.e. when slab_test8 may be used for it.
inline bool slab8_in_range(const Ray& ray) {
    const __m128 o = _mm_setr_ps(ray.origin.x, ray.origin.y, ray.origin.z, 0.0f);
    const __m128 magnitude = _mm_andnot_ps(_mm_set1_ps(-0.0f), o);
    return _mm_movemask_ps(_mm_cmplt_ps(magnitude, _mm_set1_ps(kSlab8MaxOrigin))) == 0xf;
}

/// The constants of slab_test8 for a ray that is slab8_in_range.
inline SlabRay8 prepare_slab8(const Ray& ray) {
    SlabRay8 r;
    const __m128 inv = safe_inverse4(ray.direction);
    const __m128 o = _mm_setr_ps(ray.origin.x, ray.origin.y, ray.origin.z, 0.0f);
    // oi = fl(o x inv) is within half a spacing of the exact product. pad >= the spacing of
    // floats at oi on either side: |oi| x 2^-23 for a normal oi (scaling by a power of two
    // is exact, or rounds to no less than the spacing below 2^-103), 2^-100 > 2^-149 for a
    // subnormal one; fl(a + b) >= max(a, b) for a, b >= 0. So fl(oi + pad) >= the next
    // float above oi > o x inv, and fl(oi - pad) <= the one below < o x inv (rounding is
    // monotone). The floor is a normal number, not 2^-149: with an origin coordinate 0 and
    // a plane at 0 the fma's result would be subnormal, slow on every node (4x on the
    // dragon's primary rays).
    const __m128 oi = _mm_mul_ps(o, inv);
    const __m128 magnitude = _mm_andnot_ps(_mm_set1_ps(-0.0f), oi);
    const __m128 pad =
        _mm_add_ps(_mm_mul_ps(magnitude, _mm_set1_ps(0x1p-23f)), _mm_set1_ps(0x1p-100f));
    alignas(16) float inv_a[4], near_oi[4], far_oi[4];
    _mm_store_ps(inv_a, inv);
    _mm_store_ps(near_oi, _mm_add_ps(oi, pad));
    _mm_store_ps(far_oi, _mm_sub_ps(oi, pad));
    for (std::uint32_t a = 0; a < 3; ++a) {
        r.inv[a] = _mm256_set1_ps(inv_a[a]);
        r.near_oi[a] = _mm256_set1_ps(near_oi[a]);
        r.far_oi[a] = _mm256_set1_ps(far_oi[a]);
        const bool negative = std::signbit(inv_a[a]);
        r.near[a] = 2 * a + (negative ? 1 : 0);
        r.far[a] = 2 * a + (negative ? 0 : 1);
    }
    return r;
}

/// Conservative slab test of a node's eight children in the fused form (Embree's): the
/// distance to a plane p is fma(p, inv, -oi), one rounding of p x inv - oi, instead of
/// (p - o) x inv. With oi rounded outwards (prepare_slab8) that value is, before its one
/// rounding, at most (p - o) x inv for a near plane and at least it for a far plane, so the
/// absolute error of the product o x inv only ever widens the slab; what is left are the
/// relative roundings of 1/d and of the fma, fewer than bbox.h's gamma(3), which
/// kSlabExitSlack's widening of the exit covers as before. So every box the exact ray
/// enters is entered here too (tests/accel/slab_test.cpp checks it against a test in
/// double); entry distances can differ from bbox.h's by a few ulps. Writes the entry
/// distances to t_enter (32-byte aligned) and the entry and exit vectors, a child being hit
/// where enter <= exit; each kernel turns that into a bit mask its own way. An empty child
/// (lo = +inf, hi = -inf) gets distances of +-inf, as in bbox.h's form, and is never hit.
inline void slab_test8(const WideBvhNode& node, const SlabRay8& r, float t_min, float t_max,
                       float* t_enter, __m256& enter, __m256& exit) {
    __m256 n[3], f[3];
    for (std::uint32_t a = 0; a < 3; ++a) {
        n[a] = _mm256_fmsub_ps(_mm256_load_ps(node.bounds[r.near[a]]), r.inv[a], r.near_oi[a]);
        f[a] = _mm256_fmsub_ps(_mm256_load_ps(node.bounds[r.far[a]]), r.inv[a], r.far_oi[a]);
    }
    // As bbox.h's slab_test: max and min as minps / maxps, the exit widened.
    const __m256 n01 = _mm256_max_ps(n[0], n[1]);
    const __m256 n2t = _mm256_max_ps(n[2], _mm256_set1_ps(t_min));
    enter = _mm256_max_ps(n01, n2t);
    const __m256 f01 = _mm256_min_ps(f[0], f[1]);
    const __m256 f2 = _mm256_min_ps(f01, f[2]);
    exit = _mm256_min_ps(_mm256_mul_ps(f2, _mm256_set1_ps(1.0f + kSlabExitSlack)),
                         _mm256_set1_ps(t_max));
    _mm256_store_ps(t_enter, enter);
}

/// The node half of the AVX2 and AVX-512 WideKernel policies (see wide_traversal.h) that
/// both share: the per-ray constants. Each kernel adds its own intersect_node, the one
/// place they differ (how slab_test8's lanes become a bit mask).
struct Slab8Nodes {
    using NodeRay = SlabRay8;

    static NodeRay prepare_nodes(const Ray& ray) { return prepare_slab8(ray); }
};

}  // namespace librt::detail

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
