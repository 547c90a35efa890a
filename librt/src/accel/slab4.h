#pragma once

// Private: bbox.h's slab_test on four boxes at once (SSE2, or a scalar loop elsewhere), for
// the SSE wide kernel and the scene's flat top level. Baseline code: a caller compiled for
// AVX inlines it with that encoding.

#include <librt/geometry/bbox.h>
#include <librt/geometry/ray.h>

#include <cmath>
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace librt::detail {

#if defined(__SSE2__)
/// bbox.h's safe_inverse of the direction by one vector division: a component below 1e-30
/// in magnitude becomes 1e-30 with its sign first. IEEE division is exact per lane, so the
/// three values are the scalar ones; lane 3 is 1.
inline __m128 safe_inverse4(const glm::vec3& dir) {
    const __m128 d = _mm_setr_ps(dir.x, dir.y, dir.z, 1.0f);
    const __m128 sign = _mm_set1_ps(-0.0f);
    const __m128 tiny = _mm_set1_ps(1e-30f);
    const __m128 small = _mm_cmplt_ps(_mm_andnot_ps(sign, d), tiny);
    const __m128 signed_tiny = _mm_or_ps(_mm_and_ps(d, sign), tiny);
    const __m128 fixed = _mm_or_ps(_mm_and_ps(small, signed_tiny), _mm_andnot_ps(small, d));
    return _mm_div_ps(_mm_set1_ps(1.0f), fixed);
}
#endif

/// Per-ray constants of slab_test4: origin and safe inverse direction (broadcast to four
/// lanes with SSE2) and, per axis a, the plane rows the ray enters and leaves through
/// (row 2a is lo, 2a + 1 is hi; a negative inverse enters through hi).
struct SlabRay4 {
#if defined(__SSE2__)
    __m128 origin[3];  ///< origin[a] in every lane
    __m128 inv[3];     ///< safe_inverse(direction)[a] in every lane
#else
    float origin[3];  ///< the ray's origin
    float inv[3];     ///< safe_inverse(direction)
#endif
    std::uint32_t near[3];  ///< row of the plane the ray enters through along each axis
    std::uint32_t far[3];   ///< row of the plane it leaves through
};

/// The constants of slab_test4 for a ray (which should be is_traceable).
[[nodiscard]] inline SlabRay4 prepare_slab4(const Ray& ray) {
    SlabRay4 r;
#if defined(__SSE2__)
    alignas(16) float inv[4];
    _mm_store_ps(inv, safe_inverse4(ray.direction));
#else
    const glm::vec3 inv = safe_inverse(ray.direction);
#endif
    for (std::uint32_t a = 0; a < 3; ++a) {
        const float inv_a = inv[a];
#if defined(__SSE2__)
        r.origin[a] = _mm_set1_ps(ray.origin[static_cast<int>(a)]);
        r.inv[a] = _mm_set1_ps(inv_a);
#else
        r.origin[a] = ray.origin[static_cast<int>(a)];
        r.inv[a] = inv_a;
#endif
        const bool negative = std::signbit(inv_a);
        r.near[a] = 2 * a + (negative ? 1 : 0);
        r.far[a] = 2 * a + (negative ? 0 : 1);
    }
    return r;
}

/// Conservative slab test (bbox.h's slab_test, exit widened by kSlabExitSlack) of four
/// boxes stored as plane rows: planes[p * row_stride + i] is plane p of box i, p = 0..5 for
/// lo.x, hi.x, lo.y, hi.y, lo.z, hi.z (no alignment needed). Writes each box's entry
/// distance to t_enter[0..3] and returns bit i set when box i is entered within
/// [t_min, t_max]. An empty box (lo = +inf, hi = -inf) is never entered, so it pads a row.
[[nodiscard]] inline std::uint32_t slab_test4(const float* planes, std::size_t row_stride,
                                              const SlabRay4& r, float t_min, float t_max,
                                              float* t_enter) {
#if defined(__SSE2__)
    __m128 near[3], far[3];
    for (std::uint32_t a = 0; a < 3; ++a) {
        near[a] = _mm_loadu_ps(planes + r.near[a] * row_stride);
        far[a] = _mm_loadu_ps(planes + r.far[a] * row_stride);
    }
    __m128 enter, exit;
    slab_test(near, far, r.origin, r.inv, _mm_set1_ps(t_min), _mm_set1_ps(t_max), enter, exit);
    _mm_storeu_ps(t_enter, enter);
    return static_cast<std::uint32_t>(_mm_movemask_ps(_mm_cmple_ps(enter, exit)));
#else
    std::uint32_t mask = 0;
    for (std::uint32_t i = 0; i < 4; ++i) {
        float near[3], far[3];
        for (std::uint32_t a = 0; a < 3; ++a) {
            near[a] = planes[r.near[a] * row_stride + i];
            far[a] = planes[r.far[a] * row_stride + i];
        }
        float exit;
        slab_test(near, far, r.origin, r.inv, t_min, t_max, t_enter[i], exit);
        mask |= static_cast<std::uint32_t>(t_enter[i] <= exit) << i;
    }
    return mask;
#endif
}

}  // namespace librt::detail
